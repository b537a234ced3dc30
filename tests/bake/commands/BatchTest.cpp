// `sluice-bake batch` end to end: freshness by content, --jobs, the summary, depfiles, failures.
#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "CliRun.h"
#include "TestMeshes.h"
#include "sluice/bake/commands/Cli.h"
#include "sluice/bake/sparse/SparseBaker.h"
#include "sluice/format/asset/AssetIO.h"
#include "sluice/format/support/Hash.h"

namespace sluice::bake {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using namespace clirun;

/// A folder with three small meshes (a.obj, "b b.obj", c.obj) and colliders.json baking them at
/// resolution 8 with CGAL (a few hundred points each: fast).
struct BatchFolder {
    fs::path dir;
    fs::path manifest;
    fs::path depfile;

    explicit BatchFolder(const std::string& name)
        : dir(testmesh::tempDir(name)), manifest(dir / "colliders.json"),
          depfile(dir / "colliders.d") {
        EXPECT_TRUE(testmesh::writeObj(testmesh::icoSphereSoup({0, 0, 0}, 1.0, 1), dir / "a.obj"));
        EXPECT_TRUE(testmesh::writeObj(testmesh::boxSoup({0, 0, 0}, {1, 2, 1}), dir / "b b.obj"));
        EXPECT_TRUE(
            testmesh::writeObj(testmesh::torusSoup({0, 0, 0}, 1.0, 0.3, 12, 8), dir / "c.obj"));
        writeManifest(json::array(
            {entry("a.obj", "a.slc"), entry("b b.obj", "b.slc"), entry("c.obj", "out/c.slc")}));
        fs::create_directories(dir / "out");
    }

    static json entry(const std::string& mesh, const std::string& output, int resolution = 8) {
        return {{"mesh", mesh}, {"output", output}, {"resolution", resolution}};
    }

    void writeManifest(const json& colliders) const {
        std::ofstream(manifest) << json{{"colliders", colliders}}.dump(2);
    }

    RunResult batch(std::vector<std::string> extra = {}) const {
        std::vector<std::string> args = {"batch", manifest.string(), "--depfile", depfile.string()};
        args.insert(args.end(), extra.begin(), extra.end());
        return runBake(dir, args);
    }
};

/// The status column of `label`'s row in batch's summary table ("" if there is no such row).
std::string statusOf(const std::string& summary, const std::string& label) {
    std::istringstream lines(summary);
    for (std::string line; std::getline(lines, line);) {
        std::istringstream words(line);
        std::string first, status;
        if (words >> first >> status && first == label)
            return status;
    }
    return "";
}

/// The row of `label` in batch's summary table, split into words.
std::vector<std::string> rowOf(const std::string& summary, const std::string& label) {
    std::istringstream lines(summary);
    for (std::string line; std::getline(lines, line);) {
        std::istringstream words(line);
        std::vector<std::string> row;
        for (std::string word; words >> word;)
            row.push_back(word);
        if (!row.empty() && row[0] == label)
            return row;
    }
    return {};
}

/// Bytes and time stamp of a file, to tell whether anything wrote it.
struct FileState {
    std::string bytes;
    fs::file_time_type time;
    bool operator==(const FileState&) const = default;
};

FileState stateOf(const fs::path& path) {
    return {readText(path), fs::last_write_time(path)};
}

TEST(Batch, VolumeMapsAskedForAreBakedAndAnAssetHoldingThemIsFresh) {
    const BatchFolder f("batch-volume-maps");
    json withMap = BatchFolder::entry("b b.obj", "b.slc");
    withMap["volumeMaps"] = {0.5};
    f.writeManifest(json::array({withMap}));
    RunResult run = f.batch();
    ASSERT_EQ(run.code, kExitOk) << shown(run);
    EXPECT_EQ(statusOf(run.out, "b.slc"), "baked") << run.out;
    auto asset = format::readAsset(f.dir / "b.slc");
    ASSERT_TRUE(asset) << asset.error().message();
    ASSERT_EQ(asset->volumeMaps.size(), 1u);
    EXPECT_EQ(asset->volumeMaps[0].support, 0.5);
    // Asked again, or not asked (the demo's manifest beside the build's): fresh, maps kept.
    run = f.batch();
    EXPECT_EQ(statusOf(run.out, "b.slc"), "fresh") << run.out;
    f.writeManifest(json::array({BatchFolder::entry("b b.obj", "b.slc")}));
    run = f.batch();
    EXPECT_EQ(statusOf(run.out, "b.slc"), "fresh") << run.out;
    EXPECT_EQ(format::readAsset(f.dir / "b.slc")->volumeMaps.size(), 1u);
    // A support the asset lacks: baked again, with only the maps asked for.
    withMap["volumeMaps"] = {0.6};
    f.writeManifest(json::array({withMap}));
    run = f.batch();
    EXPECT_EQ(statusOf(run.out, "b.slc"), "baked") << run.out;
    asset = format::readAsset(f.dir / "b.slc");
    ASSERT_TRUE(asset) << asset.error().message();
    ASSERT_EQ(asset->volumeMaps.size(), 1u);
    EXPECT_EQ(asset->volumeMaps[0].support, 0.6);
}

TEST(Batch, ASecondRunWithNothingChangedBakesNothing) {
    const BatchFolder f("batch-second-run");
    RunResult run = f.batch();
    ASSERT_EQ(run.code, kExitOk) << shown(run);
    EXPECT_NE(run.out.find("3 colliders: 3 baked, 0 fresh, 0 failed"), std::string::npos)
        << run.out;
    const FileState a = stateOf(f.dir / "a.slc"), c = stateOf(f.dir / "out" / "c.slc");

    run = f.batch();
    ASSERT_EQ(run.code, kExitOk) << shown(run);
    EXPECT_NE(run.out.find("0 baked, 3 fresh, 0 failed"), std::string::npos) << run.out;
    EXPECT_EQ(statusOf(run.out, "a.slc"), "fresh") << run.out;
    EXPECT_EQ(statusOf(run.out, "out/c.slc"), "fresh") << run.out;
    EXPECT_TRUE(stateOf(f.dir / "a.slc") == a) << "a fresh output must not be written";
    EXPECT_TRUE(stateOf(f.dir / "out" / "c.slc") == c);

    // The table's grid points are the asset's: 8 voxels along the longest side plus 3 of
    // padding on each side gives 15 points there.
    Result<format::ColliderAsset> asset = format::readAsset(f.dir / "a.slc");
    ASSERT_TRUE(asset.ok()) << asset.error().message();
    EXPECT_EQ(asset->meta.dims.x, 15u);
    const std::vector<std::string> row = rowOf(run.out, "a.slc");
    ASSERT_EQ(row.size(), 5u) << run.out;
    EXPECT_EQ(row[3], std::to_string(asset->pointCount()));
    EXPECT_EQ(row[4], "-") << "no validation figures yet";
}

TEST(Batch, ABandForASpacingIsBakedKeptFreshAndFollowsTheSpacing) {
    const BatchFolder f("batch-for-spacing");
    json sparse = BatchFolder::entry("a.obj", "a.slc", 16);
    sparse["sparse"] = true;
    sparse["forSpacing"] = 0.05;
    f.writeManifest(json::array({sparse}));
    RunResult run = f.batch({"--jobs", "2"}); // the child gets --sparse --for-spacing
    ASSERT_EQ(run.code, kExitOk) << shown(run);
    Result<format::ColliderAsset> a = format::readAsset(f.dir / "a.slc");
    ASSERT_TRUE(a.ok()) << a.error().message();
    const double voxel = a->meta.voxelSize;
    auto bandFor = [&](double spacing) { return *bandForVoxel(voxel, spacing, 0.0); };
    EXPECT_EQ(a->meta.bandWidth, bandFor(0.05));
    run = f.batch();
    ASSERT_EQ(run.code, kExitOk) << shown(run);
    EXPECT_EQ(statusOf(run.out, "a.slc"), "fresh") << run.out;

    // Another spacing that needs another band bakes again.
    sparse["forSpacing"] = 0.1;
    ASSERT_NE(bandFor(0.1), bandFor(0.05));
    f.writeManifest(json::array({sparse}));
    run = f.batch();
    ASSERT_EQ(run.code, kExitOk) << shown(run);
    EXPECT_EQ(statusOf(run.out, "a.slc"), "baked") << run.out;
    a = format::readAsset(f.dir / "a.slc");
    ASSERT_TRUE(a.ok());
    EXPECT_EQ(a->meta.bandWidth, bandFor(0.1));
}

TEST(Batch, SparseEntriesBakeSparseStayFreshAndRebakeWhenTheBandChanges) {
    const BatchFolder f("batch-sparse");
    json sparse = BatchFolder::entry("a.obj", "a.slc", 16);
    sparse["sparse"] = true;
    sparse["band"] = 2;
    f.writeManifest(json::array({sparse, BatchFolder::entry("c.obj", "out/c.slc")}));
    RunResult run = f.batch({"--jobs", "2"}); // the child processes get --sparse --band too
    ASSERT_EQ(run.code, kExitOk) << shown(run);
    Result<format::ColliderAsset> a = format::readAsset(f.dir / "a.slc");
    ASSERT_TRUE(a.ok()) << a.error().message();
    EXPECT_TRUE(a->sparse());
    EXPECT_EQ(a->meta.bandWidth, 2.0);
    Result<format::ColliderAsset> c = format::readAsset(f.dir / "out" / "c.slc");
    ASSERT_TRUE(c.ok()) << c.error().message();
    EXPECT_FALSE(c->sparse());

    // The sparse bake raises the padding to band + 1 and records that: still fresh.
    const FileState before = stateOf(f.dir / "a.slc");
    run = f.batch();
    ASSERT_EQ(run.code, kExitOk) << shown(run);
    EXPECT_EQ(statusOf(run.out, "a.slc"), "fresh") << run.out;
    EXPECT_TRUE(stateOf(f.dir / "a.slc") == before);

    sparse["band"] = 3;
    f.writeManifest(json::array({sparse, BatchFolder::entry("c.obj", "out/c.slc")}));
    run = f.batch();
    ASSERT_EQ(run.code, kExitOk) << shown(run);
    EXPECT_EQ(statusOf(run.out, "a.slc"), "baked") << run.out;
    EXPECT_EQ(statusOf(run.out, "out/c.slc"), "fresh") << run.out;
    a = format::readAsset(f.dir / "a.slc");
    ASSERT_TRUE(a.ok());
    EXPECT_EQ(a->meta.bandWidth, 3.0);

    // The same mesh asked dense again is not fresh either.
    f.writeManifest(json::array(
        {BatchFolder::entry("a.obj", "a.slc", 16), BatchFolder::entry("c.obj", "out/c.slc")}));
    run = f.batch();
    ASSERT_EQ(run.code, kExitOk) << shown(run);
    EXPECT_EQ(statusOf(run.out, "a.slc"), "baked") << run.out;
    a = format::readAsset(f.dir / "a.slc");
    ASSERT_TRUE(a.ok());
    EXPECT_FALSE(a->sparse());
}

TEST(Batch, TouchingAMeshWithoutChangingItsBytesBakesNothing) {
    const BatchFolder f("batch-touch");
    ASSERT_EQ(f.batch().code, kExitOk);
    const FileState a = stateOf(f.dir / "a.slc");
    // Newer than its output, as an editor saving the same content or a fresh checkout makes it.
    fs::last_write_time(f.dir / "a.obj",
                        fs::last_write_time(f.dir / "a.slc") + std::chrono::seconds(10));

    const RunResult run = f.batch();
    ASSERT_EQ(run.code, kExitOk) << shown(run);
    EXPECT_NE(run.out.find("0 baked, 3 fresh"), std::string::npos) << run.out;
    EXPECT_TRUE(stateOf(f.dir / "a.slc") == a);
}

TEST(Batch, ChangingOneMeshsBytesRebakesOnlyThatOne) {
    const BatchFolder f("batch-change");
    ASSERT_EQ(f.batch().code, kExitOk);
    const FileState a = stateOf(f.dir / "a.slc"), c = stateOf(f.dir / "out" / "c.slc");
    const std::string bBefore = readText(f.dir / "b.slc");

    // Other bytes, but an older time stamp than the output: the content decides, not the time.
    ASSERT_TRUE(testmesh::writeObj(testmesh::boxSoup({0, 0, 0}, {1, 3, 1}), f.dir / "b b.obj"));
    fs::last_write_time(f.dir / "b b.obj",
                        fs::last_write_time(f.dir / "b.slc") - std::chrono::hours(1));

    const RunResult run = f.batch();
    ASSERT_EQ(run.code, kExitOk) << shown(run);
    EXPECT_NE(run.out.find("1 baked, 2 fresh, 0 failed"), std::string::npos) << run.out;
    EXPECT_EQ(statusOf(run.out, "b.slc"), "baked") << run.out;
    EXPECT_TRUE(stateOf(f.dir / "a.slc") == a);
    EXPECT_TRUE(stateOf(f.dir / "out" / "c.slc") == c);
    EXPECT_NE(readText(f.dir / "b.slc"), bBefore);

    Result<format::ColliderAsset> b = format::readAsset(f.dir / "b.slc");
    ASSERT_TRUE(b.ok()) << b.error().message();
    Result<std::string> hash = format::hashFileHex(f.dir / "b b.obj");
    ASSERT_TRUE(hash.ok());
    EXPECT_EQ(b->meta.sourceHash, *hash);
}

TEST(Batch, OtherSettingsOrAnUnreadableOutputRebakeThatEntry) {
    const BatchFolder f("batch-settings");
    ASSERT_EQ(f.batch().code, kExitOk);

    f.writeManifest(json::array({BatchFolder::entry("a.obj", "a.slc", 10),
                                 BatchFolder::entry("b b.obj", "b.slc"),
                                 BatchFolder::entry("c.obj", "out/c.slc")}));
    RunResult run = f.batch();
    ASSERT_EQ(run.code, kExitOk) << shown(run);
    EXPECT_EQ(statusOf(run.out, "a.slc"), "baked") << run.out;
    EXPECT_NE(run.out.find("1 baked, 2 fresh"), std::string::npos) << run.out;
    Result<format::ColliderAsset> a = format::readAsset(f.dir / "a.slc");
    ASSERT_TRUE(a.ok()) << a.error().message();
    EXPECT_EQ(a->meta.bake.resolution, 10u);

    std::ofstream(f.dir / "b.slc", std::ios::binary) << "not an asset";
    run = f.batch();
    ASSERT_EQ(run.code, kExitOk) << shown(run);
    EXPECT_EQ(statusOf(run.out, "b.slc"), "baked") << run.out;
    EXPECT_TRUE(format::readAsset(f.dir / "b.slc").ok());

    // --force bakes everything, to the same bytes.
    const std::string c = readText(f.dir / "out" / "c.slc");
    run = f.batch({"--force"});
    ASSERT_EQ(run.code, kExitOk) << shown(run);
    EXPECT_NE(run.out.find("3 baked, 0 fresh"), std::string::npos) << run.out;
    EXPECT_EQ(readText(f.dir / "out" / "c.slc"), c);
}

TEST(Batch, TheDepfileListsEveryOutputWithItsMeshAndTheManifest) {
    const BatchFolder f("batch-depfile");
    const RunResult run = f.batch();
    ASSERT_EQ(run.code, kExitOk) << shown(run);

    // One Makefile rule per output, in manifest order, spaces escaped with a backslash.
    auto escaped = [](const fs::path& path) {
        std::string out;
        for (char c : path.string())
            out += c == ' ' ? std::string("\\ ") : std::string(1, c);
        return out;
    };
    const std::string manifest = escaped(f.manifest);
    const std::string expected =
        escaped(f.dir / "a.slc") + ": " + escaped(f.dir / "a.obj") + " " + manifest + "\n" +
        escaped(f.dir / "b.slc") + ": " + escaped(f.dir / "b b.obj") + " " + manifest + "\n" +
        escaped(f.dir / "out" / "c.slc") + ": " + escaped(f.dir / "c.obj") + " " + manifest + "\n";
    EXPECT_EQ(readText(f.depfile), expected);
    EXPECT_NE(readText(f.depfile).find("b\\ b.obj"), std::string::npos);

    // Written again when everything is fresh: a build system reads it after every run.
    fs::remove(f.depfile);
    ASSERT_EQ(f.batch().code, kExitOk);
    EXPECT_EQ(readText(f.depfile), expected);
}

TEST(Batch, AFailingEntryKeepsItsPreviousOutputAndTheOthersStillBake) {
    const BatchFolder f("batch-failure");
    ASSERT_EQ(f.batch().code, kExitOk);
    const FileState a = stateOf(f.dir / "a.slc");
    const std::string c = readText(f.dir / "out" / "c.slc");

    std::ofstream(f.dir / "a.obj") << "this is not a mesh\n";
    ASSERT_TRUE(
        testmesh::writeObj(testmesh::torusSoup({0, 0, 0}, 1.0, 0.4, 12, 8), f.dir / "c.obj"));
    for (const char* jobs : {"1", "2"}) {
        const RunResult run = f.batch({"--jobs", jobs});
        EXPECT_EQ(run.code, kExitBadInput) << shown(run);
        EXPECT_NE(run.err.find("a.obj"), std::string::npos) << run.err;
        EXPECT_EQ(statusOf(run.out, "a.slc"), "FAILED") << run.out;
        EXPECT_EQ(statusOf(run.out, "b.slc"), "fresh") << run.out;
        EXPECT_TRUE(stateOf(f.dir / "a.slc") == a) << "a failed bake must not touch its output";
    }
    // The first run baked c beside the failure; the second found it fresh.
    EXPECT_NE(readText(f.dir / "out" / "c.slc"), c);
    const RunResult run = f.batch();
    EXPECT_NE(run.out.find("0 baked, 2 fresh, 1 failed"), std::string::npos) << run.out;
}

TEST(Batch, TwoJobsGiveTheSameBytesAsOne) {
    // Six entries, one on the GPU (llvmpipe is enough), so CGAL bakes run beside a GPU one.
    const BatchFolder f("batch-jobs");
    json colliders = json::array();
    for (const char* mesh : {"a.obj", "b b.obj", "c.obj"})
        for (int resolution : {8, 12}) {
            const std::string name = fs::path(mesh).stem().string() + std::to_string(resolution);
            json entry = BatchFolder::entry(mesh, name + ".slc", resolution);
            if (name == "b b12")
                entry["backend"] = "gpu";
            colliders.push_back(entry);
        }
    f.writeManifest(colliders);

    RunResult run = f.batch({"--jobs", "1"});
    ASSERT_EQ(run.code, kExitOk) << shown(run);
    std::map<std::string, std::string> serial;
    for (const json& entry : colliders)
        serial[entry["output"]] = readText(f.dir / entry["output"].get<std::string>());

    run = f.batch({"--jobs", "2", "--force"});
    ASSERT_EQ(run.code, kExitOk) << shown(run);
    EXPECT_NE(run.out.find("6 baked, 0 fresh, 0 failed"), std::string::npos) << run.out;
    for (const auto& [output, bytes] : serial) {
        EXPECT_FALSE(bytes.empty()) << output;
        EXPECT_TRUE(readText(f.dir / output) == bytes) << output << " differs under --jobs 2";
    }
    Result<format::ColliderAsset> gpu = format::readAsset(f.dir / "b b12.slc");
    ASSERT_TRUE(gpu.ok()) << gpu.error().message();
    EXPECT_EQ(gpu->meta.bake.backend, "gpu");
}

TEST(Batch, ValidationFiguresShowInTheSummaryAndKeepTheOutputFresh) {
    const BatchFolder f("batch-validated");
    ASSERT_EQ(f.batch().code, kExitOk);
    RunResult run = runBake(f.dir, {"validate", (f.dir / "a.slc").string(),
                                    (f.dir / "a.obj").string(), "--write", "--quiet"});
    ASSERT_EQ(run.code, kExitOk) << shown(run);
    Result<format::ColliderAsset> a = format::readAsset(f.dir / "a.slc");
    ASSERT_TRUE(a.ok()) << a.error().message();
    ASSERT_TRUE(a->meta.validation.known);

    run = f.batch();
    ASSERT_EQ(run.code, kExitOk) << shown(run);
    EXPECT_EQ(statusOf(run.out, "a.slc"), "fresh") << run.out;
    const std::vector<std::string> row = rowOf(run.out, "a.slc");
    ASSERT_EQ(row.size(), 5u) << run.out;
    EXPECT_NE(row[4], "-") << run.out;
    EXPECT_NEAR(std::stod(row[4]), a->meta.validation.maxError,
                5e-3 * a->meta.validation.maxError + 1e-12); // printed with 3 digits
}

TEST(Batch, ABrokenManifestIsBadInputAndBakesNothing) {
    const BatchFolder f("batch-bad-manifest");
    const std::vector<std::string> broken = {
        R"({"colliders": [{"mesh": "a.obj"}]})",                      // no output
        R"({"colliders": [{"mesh": "a.obj", "output": "x.slc"},
                          {"mesh": "c.obj", "output": "./x.slc"}]})", // one output twice
        R"({"colliders": [{"mesh": "a.obj", "output": "x.slc", "resolution": "8"}]})",
        R"({"colliders": {}})",
        "not json",
    };
    for (const std::string& text : broken) {
        std::ofstream(f.manifest) << text;
        const RunResult run = f.batch();
        EXPECT_EQ(run.code, kExitBadInput) << text << '\n' << shown(run);
        EXPECT_NE(run.err.find("colliders.json"), std::string::npos) << run.err;
        EXPECT_FALSE(fs::exists(f.dir / "x.slc")) << text;
    }
    EXPECT_EQ(f.batch({"--jobs", "0"}).code, kExitBadInput);
}

/// The manifest's colliders with `field` set on the second entry (a.obj bakes first).
json withSecondEntryField(const std::string& field, const json& value) {
    json second = BatchFolder::entry("b b.obj", "b.slc");
    second[field] = value;
    return json::array({BatchFolder::entry("a.obj", "a.slc"), second});
}

TEST(Batch, ManifestErrorsNameTheFileAndTheJsonPathAndNothingBakes) {
    const BatchFolder f("batch-strict-manifest");
    const std::string m = f.manifest.string();
    const std::vector<std::pair<json, std::string>> cases = {
        {withSecondEntryField("resolutoin", 40),
         m + ": colliders[1].resolutoin: unknown key \"resolutoin\" (did you mean "
             "\"resolution\"?)"},
        {withSecondEntryField("resolution", "40"),
         m + ": colliders[1].resolution: expected a number, got the string \"40\""},
        {withSecondEntryField("sign", "foo"),
         m + ": colliders[1].sign: unknown sign method \"foo\"; expected auto, parity or "
             "winding"},
        {withSecondEntryField("storage", "f17"),
         m + ": colliders[1].storage: unknown storage \"f17\" (did you mean \"f16\"?); "
             "expected f32 or f16"},
        {withSecondEntryField("resolution", 5000),
         m + ": colliders[1].resolution: 5000 is out of range [1, 4096]"},
        {withSecondEntryField("scale", -2),
         m + ": colliders[1].scale: -2 is out of range: expected a number > 0"},
    };
    for (const auto& [colliders, message] : cases) {
        f.writeManifest(colliders);
        const RunResult run = f.batch();
        EXPECT_EQ(run.code, kExitBadInput) << shown(run);
        EXPECT_EQ(run.err, "sluice-bake batch: " + message + "\n") << shown(run);
        EXPECT_EQ(run.out, "") << shown(run);
        EXPECT_FALSE(fs::exists(f.dir / "a.slc")) << colliders.dump();
        EXPECT_FALSE(fs::exists(f.depfile)) << colliders.dump();
    }
}

TEST(Batch, CreatesTheFoldersOfItsOutputsAndDepfile) {
    const BatchFolder f("batch-creates-folders");
    f.writeManifest(json::array({BatchFolder::entry("a.obj", "new/deeper/a.slc")}));
    const fs::path depfile = f.dir / "deps" / "colliders.d";
    const RunResult run =
        runBake(f.dir, {"batch", f.manifest.string(), "--depfile", depfile.string(), "--quiet"});
    ASSERT_EQ(run.code, kExitOk) << shown(run);
    EXPECT_TRUE(format::readAsset(f.dir / "new" / "deeper" / "a.slc").ok());
    EXPECT_TRUE(fs::is_regular_file(depfile));
    // One collider, said so in the totals.
    const RunResult again = runBake(f.dir, {"batch", f.manifest.string()});
    ASSERT_EQ(again.code, kExitOk) << shown(again);
    EXPECT_NE(again.out.find("\n1 collider: 0 baked, 1 fresh, 0 failed in "), std::string::npos)
        << again.out;
}

TEST(Batch, AnOutputFolderThatCannotBeCreatedFailsBeforeAnyBake) {
    const BatchFolder f("batch-blocked-folder");
    std::ofstream(f.dir / "blocker") << "a file where a folder should be";
    f.writeManifest(json::array(
        {BatchFolder::entry("a.obj", "a.slc"), BatchFolder::entry("c.obj", "blocker/c.slc")}));
    const RunResult run = f.batch();
    EXPECT_EQ(run.code, kExitBadInput) << shown(run);
    EXPECT_EQ(run.err.rfind("sluice-bake batch: " + f.manifest.string() +
                                ": colliders[1].output: cannot create the folder '",
                            0),
              0u)
        << run.err;
    EXPECT_FALSE(fs::exists(f.dir / "a.slc"));

    // The depfile's folder is checked before the manifest is even read.
    f.writeManifest(json::array({BatchFolder::entry("a.obj", "a.slc")}));
    const RunResult dep = runBake(
        f.dir, {"batch", f.manifest.string(), "--depfile", (f.dir / "blocker" / "x.d").string()});
    EXPECT_EQ(dep.code, kExitBadInput) << shown(dep);
    EXPECT_NE(dep.err.find("cannot create the folder"), std::string::npos) << dep.err;
    EXPECT_FALSE(fs::exists(f.dir / "a.slc"));
}

} // namespace
} // namespace sluice::bake
