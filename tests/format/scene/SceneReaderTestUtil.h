// What the scene reader's tests share (SceneReaderTest.cpp, SceneReaderDynamicTest.cpp,
// SceneReaderErrorsTest.cpp): a temporary folder, the minimal scenes they vary and the
// checks of a parse.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <unistd.h>

#include "asset/AssetTestUtil.h" // PrintTo(ErrorCode)
#include "sluice/format/scene/SceneIO.h"

namespace sluice::test::scenetest {

using namespace sluice::format;
namespace fs = std::filesystem;

inline const fs::path kAssetsDir = fs::path(SLUICE_SOURCE_DIR) / "assets";
inline const SceneReadOptions kNoAssetCheck{.checkAssets = false};

// A folder under the build tree, unique to this process and test, removed afterwards.
class BuildTempDir {
public:
    BuildTempDir() {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        m_path = fs::path(SLUICE_TEST_TMP_DIR) /
                 (std::string(info ? info->name() : "scene") + "-" + std::to_string(::getpid()));
        fs::remove_all(m_path);
        fs::create_directories(m_path);
    }
    BuildTempDir(const BuildTempDir&) = delete;
    BuildTempDir& operator=(const BuildTempDir&) = delete;
    ~BuildTempDir() {
        std::error_code ec;
        fs::remove_all(m_path, ec);
    }
    fs::path write(const std::string& name, const std::string& text) const {
        const fs::path p = m_path / name;
        std::ofstream(p, std::ios::binary) << text;
        return p;
    }
    const fs::path& path() const { return m_path; }

private:
    fs::path m_path;
};

// One box of 5 x 5 x 5 particles at the default spacing 0.02.
inline const std::string kMinimal =
    R"({"fluid": [{"box": {"min": [0, 0, 0], "max": [0.1, 0.1, 0.1]}}]})";

inline Scene parseOk(const std::string& json, const SceneReadOptions& options = kNoAssetCheck) {
    auto r = parseScene(json, "scene.json", options);
    EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message()) << "\n" << json;
    return r.ok() ? std::move(r).value() : Scene{};
}

// Parses `json` as scene.json, expects `code` and a message holding the file name and every
// one of `parts` (the JSON path, the problem).
inline void expectError(const std::string& json, ErrorCode code,
                        const std::vector<std::string>& parts,
                        const SceneReadOptions& options = kNoAssetCheck) {
    const auto r = parseScene(json, "scene.json", options);
    ASSERT_FALSE(r.ok()) << "accepted:\n" << json;
    EXPECT_EQ(r.error().code, code) << r.error().message() << "\n" << json;
    const std::string& m = r.error().detail;
    EXPECT_EQ(m.rfind("scene.json", 0), 0u) << m;
    for (const std::string& part : parts)
        EXPECT_NE(m.find(part), std::string::npos) << "'" << part << "' not in: " << m;
}

// The minimal scene with `simulation` set to the given object body.
inline std::string withSimulation(const std::string& body) {
    return R"({"simulation": {)" + body +
           R"(}, "fluid": [{"box": {"min": [0, 0, 0], "max": [0.1, 0.1, 0.1]}}]})";
}

// The minimal scene plus one collider with the given object body.
inline std::string withCollider(const std::string& body) {
    return R"({"fluid": [{"box": {"min": [0, 0, 0], "max": [0.1, 0.1, 0.1]}}],
               "colliders": [{"asset": "a.slc"}, {)" +
           body + "}]}";
}

// The minimal scene plus a static collider and colliders[1], "b.slc", with "dynamic" set to
// the given object body and `more` (keys of the collider itself, each with a leading comma).
inline std::string withDynamic(const std::string& body, const std::string& more = {}) {
    return withCollider(R"("asset": "b.slc", "dynamic": {)" + body + "}" + more);
}

// A scene of one emitter: position [0, 1, 0], direction [0, -1, 0], radius 0.04, speed 1, with
// `changes` replacing or adding keys (a value of "" removes the key).
inline std::string
withEmitter(const std::vector<std::pair<std::string, std::string>>& changes = {}) {
    std::vector<std::pair<std::string, std::string>> keys = {
        {"position", "[0, 1, 0]"}, {"direction", "[0, -1, 0]"}, {"radius", "0.04"}, {"speed", "1"}};
    for (const auto& change : changes) {
        auto it = std::find_if(keys.begin(), keys.end(),
                               [&](const auto& k) { return k.first == change.first; });
        if (it == keys.end())
            keys.push_back(change);
        else
            it->second = change.second;
    }
    std::string body;
    for (const auto& [key, value] : keys)
        if (!value.empty())
            body += (body.empty() ? "\"" : ", \"") + key + "\": " + value;
    return R"({"emitters": [{)" + body + "}]}";
}

inline std::string readText(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

// Brute-force lattice counts from docs/pbf.md, in double, to check the reader's own.
inline std::uint64_t bruteSphere(double radius, double s) {
    const double reach = radius - s / 2;
    const int k = int(std::ceil(reach / s)) + 1;
    std::uint64_t n = 0;
    for (int i = -k; i <= k; ++i)
        for (int j = -k; j <= k; ++j)
            for (int l = -k; l <= k; ++l)
                n += s * std::sqrt(double(i * i + j * j + l * l)) <= reach;
    return n;
}

inline std::uint64_t bruteDisc(double radius, double s) {
    const int k = int(radius / s) + 2;
    std::uint64_t n = 0;
    for (int a = -k; a <= k; ++a)
        for (int b = -k; b <= k; ++b)
            n += s * s * (a * a + b * b) <= radius * radius;
    return n;
}
} // namespace sluice::test::scenetest
