// What the mesh import tests share (MeshImportTest.cpp, MeshImportPlyTest.cpp): a file written
// for a test and the check of a refused import.
#pragma once

#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <string>

#include <gtest/gtest.h>

#include "TestMeshes.h"
#include "sluice/bake/import/MeshImport.h"

namespace sluice::bake::importtest {

inline std::filesystem::path writeText(const std::string& folder, const std::string& name,
                                       const std::string& text) {
    const std::filesystem::path path = testmesh::tempDir(folder) / name;
    std::ofstream(path) << text;
    return path;
}

/// Expects importing `path` to fail with `code`, naming each of `parts` in its detail.
inline void expectRefused(const std::filesystem::path& path, ErrorCode code,
                          std::initializer_list<std::string> parts = {},
                          const ImportOptions& options = {}) {
    Result<ImportedMesh> mesh = importMesh(path, options);
    ASSERT_FALSE(mesh.ok()) << path << " was accepted";
    EXPECT_EQ(mesh.error().code, code) << mesh.error().message();
    for (const std::string& part : parts)
        EXPECT_NE(mesh.error().detail.find(part), std::string::npos)
            << "no \"" << part << "\" in: " << mesh.error().detail;
}

} // namespace sluice::bake::importtest
