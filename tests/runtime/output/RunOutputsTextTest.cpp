// What a run prints and writes beside its statistics, without a GL context: the body
// trajectory table's columns and quoting, the durations of the progress line, and when a run is
// warned about as slow.
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "sluice/format/asset/AssetIO.h"

#include "output/BodiesCsv.h"
#include "play/RunProgress.h"

namespace sluice::rt {
namespace {

std::vector<std::string> splitCsvLine(const std::string& line) {
    std::vector<std::string> fields;
    std::string field;
    bool quoted = false;
    for (std::size_t i = 0; i < line.size(); ++i) {
        const char c = line[i];
        if (quoted && c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
            field += '"';
            ++i;
        } else if (c == '"') {
            quoted = !quoted;
        } else if (c == ',' && !quoted) {
            fields.push_back(field);
            field.clear();
        } else {
            field += c;
        }
    }
    fields.push_back(field);
    return fields;
}

BodyState movingBody() {
    BodyState b;
    b.collider = 2;
    b.position = {0.5f, 0.25f, -0.125f};
    b.orientation = glm::quat(0.5f, 0.5f, -0.5f, 0.5f); // w, x, y, z
    b.linearVelocity = {1.0f, -2.0f, 3.0f};
    b.angularVelocity = {-0.5f, 0.0f, 0.25f};
    b.submergedShare = 0.625;
    b.force = {0.0f, 9.8125f, -1.0f};
    b.pose.translation = {0.375f, 0.25f, -0.0625f};
    return b;
}

TEST(BodiesCsv, EveryRowHasTheHeadersColumnsInItsOrder) {
    format::Scene scene;
    scene.colliders.resize(3);
    scene.colliders[2].asset = "crate.slc";
    const std::vector<std::string> header =
        splitCsvLine(bodiesCsvHeader().substr(0, bodiesCsvHeader().size() - 1));
    ASSERT_EQ(header.size(), 25u);
    const std::string rows = bodiesCsvRows(scene, 12, 0.2, {BodyState{}, movingBody()});
    std::istringstream in(rows);
    std::string line;
    std::vector<std::vector<std::string>> parsed;
    while (std::getline(in, line))
        parsed.push_back(splitCsvLine(line));
    ASSERT_EQ(parsed.size(), 2u);
    const std::vector<std::string>& row = parsed[1];
    ASSERT_EQ(row.size(), header.size());
    auto at = [&](const std::string& column) {
        for (std::size_t i = 0; i < header.size(); ++i)
            if (header[i] == column)
                return row[i];
        ADD_FAILURE() << "no column " << column;
        return std::string();
    };
    EXPECT_EQ(at("step"), "12");
    EXPECT_EQ(at("body"), "1");
    EXPECT_EQ(at("collider"), "2");
    EXPECT_EQ(at("asset"), "crate.slc");
    EXPECT_EQ(std::stod(at("time")), 0.2);
    EXPECT_EQ(std::stod(at("origin_x")), 0.375);
    EXPECT_EQ(std::stod(at("origin_z")), -0.0625);
    EXPECT_EQ(std::stod(at("centre_of_mass_x")), 0.5);
    EXPECT_EQ(std::stod(at("centre_of_mass_z")), -0.125);
    EXPECT_EQ(std::stod(at("orientation_x")), 0.5);
    EXPECT_EQ(std::stod(at("orientation_y")), -0.5);
    EXPECT_EQ(std::stod(at("orientation_w")), 0.5);
    EXPECT_EQ(std::stod(at("linear_velocity_y")), -2.0);
    EXPECT_EQ(std::stod(at("angular_velocity_z")), 0.25);
    EXPECT_EQ(std::stod(at("submerged_share")), 0.625);
    EXPECT_EQ(std::stod(at("force_y")), 9.8125);
}

TEST(BodiesCsv, AnAssetNameWithACommaOrAQuoteIsQuoted) {
    format::Scene scene;
    scene.colliders.resize(1);
    scene.colliders[0].asset = "rocks, \"big\".slc";
    const std::string rows = bodiesCsvRows(scene, 0, 0.0, {BodyState{}});
    EXPECT_NE(rows.find(",\"rocks, \"\"big\"\".slc\","), std::string::npos) << rows;
    const std::vector<std::string> fields = splitCsvLine(rows.substr(0, rows.size() - 1));
    ASSERT_EQ(fields.size(), 25u);
    EXPECT_EQ(fields[4], "rocks, \"big\".slc");
}

TEST(RunProgress, DurationsReadAsPeopleWriteThem) {
    EXPECT_EQ(formatDuration(0.4), "0 s");
    EXPECT_EQ(formatDuration(59.4), "59 s");
    EXPECT_EQ(formatDuration(247.0), "4:07");
    EXPECT_EQ(formatDuration(3600.0 + 5 * 60 + 9), "1:05:09");
    EXPECT_EQ(formatDuration(-1.0), "?");
}

TEST(RunProgress, OnlyASoftwareRendererRunOfMinutesIsWarnedAbout) {
    const std::string llvmpipe = "llvmpipe (LLVM 15.0.6, 256 bits)";
    EXPECT_TRUE(isSoftwareRenderer(llvmpipe));
    EXPECT_FALSE(isSoftwareRenderer("NVIDIA H200/PCIe/SSE2"));
    // The shipped dam-break (4,725 particles, 4 substeps) for 60 steps: seconds, no warning.
    EXPECT_FALSE(slowRunWarning(llvmpipe, 4725, 4, 60, 2));
    // For 6,000 steps (100 s of simulated time): about 12 min on two cores.
    const auto warning = slowRunWarning(llvmpipe, 4725, 4, 6000, 2);
    ASSERT_TRUE(warning);
    EXPECT_NE(warning->find("llvmpipe"), std::string::npos) << *warning;
    EXPECT_NE(warning->find("4725 particles x 6000 steps"), std::string::npos) << *warning;
    // The same run on a GPU says nothing.
    EXPECT_FALSE(slowRunWarning("NVIDIA H200/PCIe/SSE2", 4725, 4, 6000, 2));
    // More cores share the work: 64 cores bring it under the limit.
    EXPECT_FALSE(slowRunWarning(llvmpipe, 4725, 4, 6000, 64));
}

TEST(RunOutputsText, ALoadThatBuiltVolumeMapsSaysWhichAndTheOptionThatBakesThem) {
    format::Scene scene;
    scene.simulation.kernelRadius = 0.05f;
    format::SceneCollider tank, ball;
    tank.asset = "tank.slc";
    ball.asset = "sphere.slc";
    ball.scale = 0.4f;
    scene.colliders = {tank, ball};
    EXPECT_FALSE(volumeMapNote(scene, VolumeMapLoad{2, 0, 0.0, {}})); // every map baked
    const auto note = volumeMapNote(scene, VolumeMapLoad{0, 2, 4.2, {0, 1}});
    ASSERT_TRUE(note);
    EXPECT_NE(note->find("built 2 volume maps at load in"), std::string::npos) << *note;
    EXPECT_NE(note->find("tank.slc (--volume-map 0.05), sphere.slc (--volume-map 0.125)"),
              std::string::npos)
        << *note;
}

TEST(RunOutputsText, VolumeMapsThatWouldTakeLongOnASoftwareRendererAreWarnedAboutBeforeTheLoad) {
    const std::string llvmpipe = "llvmpipe (LLVM 15.0.6, 256 bits)";
    auto tank = format::readAsset(std::filesystem::path(SLUICE_BUILD_ASSETS_DIR) / "tank.slc");
    ASSERT_TRUE(tank) << tank.error().message();
    format::Scene scene;
    scene.simulation.spacing = 0.02f;
    scene.simulation.kernelRadius = 0.04f;
    format::SceneCollider collider;
    collider.asset = "tank.slc";
    scene.colliders.push_back(collider);
    // The shipped tank carries its map for this h; without it the load builds one.
    ASSERT_NE(tank->volumeMapFor(0.04), nullptr);
    const std::vector<format::ColliderAsset> baked{*tank};
    EXPECT_EQ(volumeMapWork(scene, baked).points, 0u);
    tank->volumeMaps.clear();
    const std::vector<format::ColliderAsset> assets{*tank};
    // Without a baked map the load builds one per static collider.
    const VolumeMapWork work = volumeMapWork(scene, assets);
    EXPECT_EQ(work.points, 514596u); // the tank's grid
    // h = 5.33 of its 7.5 mm cells: a support ball of 635 cells a point.
    EXPECT_NEAR(work.denseReads / double(work.points), 635.5, 0.5);
    EXPECT_EQ(work.sparseReads, 0.0);
    // Measured: 2.1 s on two cores. No warning, nor on a GPU.
    EXPECT_FALSE(slowLoadWarning(llvmpipe, work, 2));
    // At half the voxel size (8 times the points and the cells of a ball): about 2 min.
    VolumeMapWork finer = work;
    finer.points *= 8;
    finer.denseReads *= 64;
    const auto warning = slowLoadWarning(llvmpipe, finer, 2);
    ASSERT_TRUE(warning);
    EXPECT_NE(warning->find("4116768 grid points"), std::string::npos) << *warning;
    EXPECT_NE(warning->find("llvmpipe"), std::string::npos) << *warning;
    EXPECT_FALSE(slowLoadWarning("NVIDIA H200/PCIe/SSE2", finer, 2));
    // At h = 20 cm (27 cells) the quadrature reads every fifth grid value: as many reads again.
    scene.simulation.kernelRadius = 0.2f;
    EXPECT_NEAR(volumeMapWork(scene, assets).denseReads / double(work.points), 635.5, 0.5);
    // At h = 2 cm (2.7 cells) it reads the field trilinearly at h / 5: 8 x 524 values a point.
    scene.simulation.kernelRadius = 0.02f;
    EXPECT_NEAR(volumeMapWork(scene, assets).denseReads / double(work.points), 8 * 523.6, 1.0);
    // A dynamic body keeps the closed form: nothing to build.
    scene.colliders[0].dynamic = format::DynamicBody{};
    EXPECT_EQ(volumeMapWork(scene, assets).points, 0u);
}

} // namespace
} // namespace sluice::rt
