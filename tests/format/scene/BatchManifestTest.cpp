// The batch manifest reader: defaults, resolved paths, and every error naming the JSON path.
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "asset/AssetTestUtil.h" // PrintTo(ErrorCode)
#include "sluice/format/scene/BatchManifest.h"
#include "support/TempDir.h"

namespace sluice::test {
namespace {

using namespace sluice::format;
namespace fs = std::filesystem;

const fs::path kManifest = fs::path("jobs") / "colliders.json";

/// The manifest's error message, or "" if it reads.
std::string errorOf(const std::string& json) {
    Result<BatchManifest> manifest = parseBatchManifest(json, kManifest);
    return manifest ? std::string() : manifest.error().detail;
}

ErrorCode codeOf(const std::string& json) {
    Result<BatchManifest> manifest = parseBatchManifest(json, kManifest);
    EXPECT_FALSE(manifest.ok()) << json;
    return manifest ? ErrorCode::Io : manifest.error().code;
}

/// `{"colliders": [{"mesh": "a.obj", "output": "a.slc"}, {"mesh": "b.obj", "output": "b.slc",
/// FIELDS}]}`: the second entry carries the fields under test.
std::string secondEntryWith(const std::string& fields) {
    return R"({"colliders": [{"mesh": "a.obj", "output": "a.slc"},
                             {"mesh": "b.obj", "output": "b.slc", )" +
           fields + "}]}";
}

TEST(BatchManifest, ReadsEveryFieldAndResolvesPathsAgainstTheManifestsFolder) {
    Result<BatchManifest> manifest = parseBatchManifest(
        R"({"colliders": [{"mesh": "meshes/rock.obj", "output": "out/rock.slc",
                           "voxelSize": 0.25, "padding": 0, "sign": "winding",
                           "storage": "f16", "scale": 2, "backend": "cgal"},
                          {"mesh": "b.obj", "output": "b.slc", "resolution": 40}]})",
        kManifest);
    ASSERT_TRUE(manifest) << manifest.error().message();
    ASSERT_EQ(manifest->colliders.size(), 2u);
    const BatchEntry& rock = manifest->colliders[0];
    EXPECT_EQ(rock.mesh, "meshes/rock.obj");
    EXPECT_EQ(rock.meshPath, fs::path("jobs") / "meshes/rock.obj");
    EXPECT_EQ(rock.outputPath, fs::path("jobs") / "out/rock.slc");
    EXPECT_EQ(rock.voxelSize, 0.25);
    EXPECT_EQ(rock.padding, 0.0);
    EXPECT_EQ(rock.sign, "winding");
    EXPECT_EQ(rock.storage, "f16");
    EXPECT_EQ(rock.scale, 2.0);
    EXPECT_EQ(rock.backend, "cgal");
    const BatchEntry& b = manifest->colliders[1];
    EXPECT_EQ(b.resolution, 40u);
    EXPECT_EQ(b.voxelSize, 0.0);
    EXPECT_EQ(b.padding, 3.0);
    EXPECT_EQ(b.sign, "auto");
    EXPECT_EQ(b.storage, "f32");
    EXPECT_EQ(b.backend, "auto");
}

TEST(BatchManifest, RejectsAnUnknownKeySuggestingTheClosestKnownOne) {
    EXPECT_EQ(errorOf(secondEntryWith(R"("resolutoin": 40)")),
              "jobs/colliders.json: colliders[1].resolutoin: unknown key \"resolutoin\" (did you "
              "mean \"resolution\"?)");
    EXPECT_EQ(errorOf(R"({"colliders": [], "colider": []})"),
              "jobs/colliders.json: colider: unknown key \"colider\" (did you mean "
              "\"colliders\"?)");
}

TEST(BatchManifest, NamesTheJsonPathOfAValueOfTheWrongType) {
    EXPECT_EQ(errorOf(secondEntryWith(R"("resolution": "40")")),
              "jobs/colliders.json: colliders[1].resolution: expected a number, got the string "
              "\"40\"");
    EXPECT_EQ(errorOf(secondEntryWith(R"("padding": true)")),
              "jobs/colliders.json: colliders[1].padding: expected a number, got true");
    EXPECT_EQ(errorOf(secondEntryWith(R"("sign": 1)")),
              "jobs/colliders.json: colliders[1].sign: expected a string, got the number 1");
    EXPECT_EQ(errorOf(R"({"colliders": {}})"),
              "jobs/colliders.json: colliders: expected an array, got an object");
    EXPECT_EQ(errorOf(R"({"colliders": [{"mesh": "a.obj"}]})"),
              "jobs/colliders.json: colliders[0]: missing required key \"output\"");
}

TEST(BatchManifest, RejectsValuesTheBakeFlagsRejectNamingTheField) {
    EXPECT_EQ(errorOf(secondEntryWith(R"("resolution": 5000)")),
              "jobs/colliders.json: colliders[1].resolution: 5000 is out of range [1, 4096]");
    EXPECT_EQ(errorOf(secondEntryWith(R"("resolution": 8.5)")),
              "jobs/colliders.json: colliders[1].resolution: expected an integer, got 8.5");
    EXPECT_EQ(errorOf(secondEntryWith(R"("voxelSize": 0)")),
              "jobs/colliders.json: colliders[1].voxelSize: 0 is out of range: expected a number "
              "> 0");
    EXPECT_EQ(errorOf(secondEntryWith(R"("padding": -1)")),
              "jobs/colliders.json: colliders[1].padding: -1 is out of range: expected a number "
              ">= 0");
    EXPECT_EQ(errorOf(secondEntryWith(R"("scale": NaN)")),
              "jobs/colliders.json: colliders[1].scale: NaN is not a finite number");
    EXPECT_EQ(codeOf(secondEntryWith(R"("scale": Infinity)")), ErrorCode::NonFinite);
    EXPECT_EQ(errorOf(secondEntryWith(R"("resolution": 8, "voxelSize": 0.1)")),
              "jobs/colliders.json: colliders[1]: give \"resolution\" or \"voxelSize\", not both");
    EXPECT_EQ(codeOf(secondEntryWith(R"("resolution": 0)")), ErrorCode::InvalidArgument);
}

TEST(BatchManifest, RejectsUnknownEnumerationValuesListingTheKnownOnes) {
    EXPECT_EQ(errorOf(secondEntryWith(R"("sign": "foo")")),
              "jobs/colliders.json: colliders[1].sign: unknown sign method \"foo\"; expected "
              "auto, parity or winding");
    EXPECT_EQ(errorOf(secondEntryWith(R"("sign": "windnig")")),
              "jobs/colliders.json: colliders[1].sign: unknown sign method \"windnig\" (did you "
              "mean \"winding\"?); expected auto, parity or winding");
    EXPECT_EQ(errorOf(secondEntryWith(R"("storage": "f33")")),
              "jobs/colliders.json: colliders[1].storage: unknown storage \"f33\" (did you mean "
              "\"f32\"?); expected f32 or f16");
    EXPECT_EQ(errorOf(secondEntryWith(R"("backend": "vulkan")")),
              "jobs/colliders.json: colliders[1].backend: unknown backend \"vulkan\"; expected "
              "auto, gpu or cgal");
}

TEST(BatchManifest, ReadsSparseEntriesAndRejectsWhatBakeSparseRejects) {
    auto manifest = format::parseBatchManifest(
        R"({"colliders": [{"mesh": "a.obj", "output": "a.slc", "sparse": true, "band": 4.5},
                          {"mesh": "b.obj", "output": "b.slc", "sparse": true},
                          {"mesh": "c.obj", "output": "c.slc"}]})",
        "jobs/colliders.json");
    ASSERT_TRUE(manifest.ok()) << manifest.error().message();
    EXPECT_TRUE(manifest->colliders[0].sparse);
    EXPECT_EQ(manifest->colliders[0].band, 4.5);
    EXPECT_TRUE(manifest->colliders[1].sparse);
    EXPECT_EQ(manifest->colliders[1].band, 3.0) << "bake --sparse's default band";
    EXPECT_FALSE(manifest->colliders[2].sparse);

    EXPECT_EQ(errorOf(secondEntryWith(R"("band": 3)")),
              "jobs/colliders.json: colliders[1].band: a band is for sparse assets: add "
              "\"sparse\": true");
    EXPECT_EQ(errorOf(secondEntryWith(R"("sparse": true, "band": 65)")),
              "jobs/colliders.json: colliders[1].band: 65 is out of range: expected 1 to 64 "
              "voxels");
    EXPECT_EQ(errorOf(secondEntryWith(R"("sparse": "yes")")),
              "jobs/colliders.json: colliders[1].sparse: expected true or false, got a string");
    EXPECT_EQ(codeOf(secondEntryWith(R"("sparse": true, "storage": "f16")")),
              ErrorCode::InvalidArgument);
    EXPECT_EQ(codeOf(secondEntryWith(R"("sparse": true, "band": NaN)")), ErrorCode::NonFinite);
    // Either backend bakes sparse.
    for (const char* backend : {R"("backend": "gpu")", R"("backend": "cgal")"}) {
        auto entry = format::parseBatchManifest(
            secondEntryWith(std::string(R"("sparse": true, )") + backend), kManifest);
        ASSERT_TRUE(entry.ok()) << entry.error().message();
        EXPECT_TRUE(entry->colliders[1].sparse);
    }
}

TEST(BatchManifest, ReadsABandForASpacingAndRejectsWhatBakeRejects) {
    auto manifest = format::parseBatchManifest(
        R"({"colliders": [{"mesh": "a.obj", "output": "a.slc", "sparse": true, "forSpacing": 0.02},
                          {"mesh": "b.obj", "output": "b.slc", "sparse": true,
                           "forSpacing": 0.01, "forKernelRadius": 0.03}]})",
        "jobs/colliders.json");
    ASSERT_TRUE(manifest.ok()) << manifest.error().message();
    EXPECT_EQ(manifest->colliders[0].forSpacing, 0.02);
    EXPECT_EQ(manifest->colliders[0].forKernelRadius, 0.0) << "the default kernel";
    EXPECT_EQ(manifest->colliders[1].forSpacing, 0.01);
    EXPECT_EQ(manifest->colliders[1].forKernelRadius, 0.03);

    EXPECT_EQ(errorOf(secondEntryWith(R"("forSpacing": 0.02)")),
              "jobs/colliders.json: colliders[1].forSpacing: a band is for sparse assets: add "
              "\"sparse\": true");
    EXPECT_EQ(errorOf(secondEntryWith(R"("sparse": true, "band": 4, "forSpacing": 0.02)")),
              "jobs/colliders.json: colliders[1]: give \"band\" or \"forSpacing\", not both");
    EXPECT_EQ(errorOf(secondEntryWith(R"("sparse": true, "forKernelRadius": 0.04)")),
              "jobs/colliders.json: colliders[1].forKernelRadius: a kernel radius goes with "
              "\"forSpacing\"");
    EXPECT_EQ(codeOf(secondEntryWith(R"("sparse": true, "forSpacing": 0)")),
              ErrorCode::InvalidArgument);
    EXPECT_EQ(codeOf(secondEntryWith(R"("sparse": true, "forSpacing": -1)")),
              ErrorCode::InvalidArgument);
    EXPECT_EQ(codeOf(secondEntryWith(R"("sparse": true, "forSpacing": "2cm")")),
              ErrorCode::BadMetadata);
}

TEST(BatchManifest, ReadsVolumeMapsAndRejectsWhatBakeRejects) {
    auto manifest = format::parseBatchManifest(
        secondEntryWith(R"("volumeMaps": [0.04, 0.0266667])"), "jobs/colliders.json");
    ASSERT_TRUE(manifest.ok()) << manifest.error().message();
    EXPECT_TRUE(manifest->colliders[0].volumeMaps.empty());
    EXPECT_EQ(manifest->colliders[1].volumeMaps, (std::vector<double>{0.04, 0.0266667}));

    EXPECT_EQ(errorOf(secondEntryWith(R"("volumeMaps": [0.04, 0.040001])")),
              "jobs/colliders.json: colliders[1].volumeMaps[1]: 0.040001 is given twice");
    EXPECT_EQ(errorOf(secondEntryWith(R"("volumeMaps": [1, 2, 3, 4, 5, 6, 7, 8, 9])")),
              "jobs/colliders.json: colliders[1].volumeMaps: 9 volume maps; at most 8");
    EXPECT_EQ(codeOf(secondEntryWith(R"("volumeMaps": [0])")), ErrorCode::InvalidArgument);
    EXPECT_EQ(codeOf(secondEntryWith(R"("volumeMaps": 0.04)")), ErrorCode::BadMetadata);
    EXPECT_EQ(codeOf(secondEntryWith(R"("volumeMaps": ["4cm"])")), ErrorCode::BadMetadata);
}

TEST(BatchManifest, RejectsTwoEntriesWritingTheSameOutput) {
    EXPECT_EQ(errorOf(R"({"colliders": [{"mesh": "a.obj", "output": "x.slc"},
                                        {"mesh": "b.obj", "output": "./x.slc"}]})"),
              "jobs/colliders.json: colliders[1].output: \"./x.slc\" is written by an earlier "
              "entry too");
}

TEST(BatchManifest, SyntaxErrorsNameTheLineAndColumn) {
    EXPECT_EQ(errorOf("{\"colliders\": [\n  {\"mesh\": \"a.obj\",}\n]}"),
              "jobs/colliders.json:2:20: colliders[0].mesh: JSON syntax error: missing a key (a "
              "quoted string) in an object");
}

TEST(BatchManifest, ReadsAFileAndNamesAMissingOne) {
    TempDir dir;
    const fs::path file = dir.path() / "m.json";
    std::ofstream(file) << R"({"colliders": [{"mesh": "a.obj", "output": "a.slc"}]})";
    Result<BatchManifest> manifest = readBatchManifest(file);
    ASSERT_TRUE(manifest) << manifest.error().message();
    EXPECT_EQ(manifest->colliders.at(0).outputPath, dir.path() / "a.slc");

    Result<BatchManifest> missing = readBatchManifest(dir.path() / "none.json");
    ASSERT_FALSE(missing);
    EXPECT_EQ(missing.error().code, ErrorCode::Io);
    EXPECT_NE(missing.error().detail.find("none.json: cannot read the manifest"), std::string::npos)
        << missing.error().detail;
}

} // namespace
} // namespace sluice::test
