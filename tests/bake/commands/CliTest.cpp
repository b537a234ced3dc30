// The sluice-bake program end to end: subcommands, JSON output, exit codes and bad input.
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "CliRun.h"
#include "TestMeshes.h"
#include "sluice/bake/commands/Cli.h"
#include "sluice/format/asset/AssetIO.h"

namespace sluice::bake {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using namespace clirun;

/// Points of the grid bakeSphere makes: 16 voxels across the sphere, 3 of padding each side.
constexpr int kSpherePoints = 23 * 23 * 23;

/// Bakes the demo sphere at a small resolution into dir/name (a few thousand points, fast).
fs::path bakeSphere(const fs::path& dir, const std::string& name,
                    const std::vector<std::string>& extra = {}) {
    const fs::path out = dir / name;
    std::vector<std::string> args = {
        "bake", kSphereObj.string(), "-o", out.string(), "--resolution", "16", "--quiet"};
    args.insert(args.end(), extra.begin(), extra.end());
    const RunResult run = runBake(dir, args);
    EXPECT_EQ(run.code, kExitOk) << shown(run);
    return out;
}

TEST(Cli, VersionPrintsTheToolNameAndVersion) {
    const fs::path dir = testmesh::tempDir("cli-version");
    const RunResult run = runBake(dir, {"--version"});
    EXPECT_EQ(run.code, kExitOk) << shown(run);
    EXPECT_EQ(run.out.rfind("sluice-bake ", 0), 0u) << run.out;
    EXPECT_NE(run.out.find_first_of("0123456789"), std::string::npos) << run.out;
}

TEST(Cli, HelpExitsZeroAndListsEverySubcommandAndExitCode) {
    const fs::path dir = testmesh::tempDir("cli-help");
    const RunResult run = runBake(dir, {"--help"});
    EXPECT_EQ(run.code, kExitOk) << shown(run);
    for (const char* word : {"bake", "validate", "info", "export", "gl-info", "Exit codes"})
        EXPECT_NE(run.out.find(word), std::string::npos) << word << "\n" << run.out;
    const RunResult sub = runBake(dir, {"bake", "--help"});
    EXPECT_EQ(sub.code, kExitOk) << shown(sub);
    EXPECT_NE(sub.out.find("--voxel-size"), std::string::npos) << sub.out;
}

TEST(Cli, UnknownFlagsAndMissingCommandsAreBadInput) {
    const fs::path dir = testmesh::tempDir("cli-usage");
    EXPECT_EQ(runBake(dir, {"--no-such-flag"}).code, kExitBadInput);
    EXPECT_EQ(runBake(dir, {}).code, kExitBadInput);
    EXPECT_EQ(runBake(dir, {"frobnicate"}).code, kExitBadInput);
    const fs::path output = dir / "x.slc";
    const RunResult run =
        runBake(dir, {"bake", kSphereObj.string(), "-o", output.string(), "--frob"});
    EXPECT_EQ(run.code, kExitBadInput) << shown(run);
    EXPECT_NE(run.err.find("--frob"), std::string::npos) << run.err;
    EXPECT_FALSE(fs::exists(output));
}

TEST(Cli, BakeInfoValidateExportWorkTogether) {
    const fs::path dir = testmesh::tempDir("cli-pipeline");
    const fs::path asset = dir / "sphere.slc";
    const RunResult bake =
        runBake(dir, {"bake", kSphereObj.string(), "-o", asset.string(), "--backend", "cgal",
                      "--resolution", "16", "--padding", "2"});
    ASSERT_EQ(bake.code, kExitOk) << shown(bake);
    ASSERT_TRUE(fs::exists(asset));
    for (const char* word : {"sign", "parity", "1280 triangles", "closed", "voxels/s"})
        EXPECT_NE(bake.out.find(word), std::string::npos) << word << "\n" << bake.out;

    const RunResult info = runBake(dir, {"info", asset.string(), "--json"});
    ASSERT_EQ(info.code, kExitOk) << shown(info);
    const json meta = json::parse(info.out);
    // The sphere's box is 0.5 wide: 16 voxels plus 2 of padding on each side, 21 points.
    EXPECT_EQ(meta["dims"], json::array({21, 21, 21}));
    EXPECT_NEAR(meta["voxelSize"].get<double>(), 0.5 / 16.0, 1e-6);
    EXPECT_EQ(meta["storage"], "f32");
    EXPECT_EQ(meta["sourceFile"], "sphere.obj");
    EXPECT_EQ(meta["sourceHash"].get<std::string>().size(), 16u);
    EXPECT_EQ(meta["toolVersion"].get<std::string>().rfind("sluice-bake ", 0), 0u);
    EXPECT_EQ(meta["bake"]["backend"], "cgal");
    EXPECT_EQ(meta["bake"]["resolution"], 16);
    EXPECT_EQ(meta["bake"]["padding"], 2.0);
    EXPECT_EQ(meta["bake"]["signMode"], "auto");
    EXPECT_EQ(meta["bake"]["signUsed"], "parity");
    EXPECT_EQ(meta["bake"]["scale"], 1.0);
    EXPECT_EQ(meta["mesh"]["triangles"], 1280);
    EXPECT_EQ(meta["mesh"]["vertices"], 642);
    EXPECT_EQ(meta["mesh"]["closed"], true);
    EXPECT_EQ(meta["mesh"]["selfIntersecting"], false);
    EXPECT_EQ(meta["validation"]["known"], false);
    EXPECT_EQ(meta["header"]["major"], 1);
    EXPECT_EQ(meta["header"]["fileSize"], fs::file_size(asset));
    // Deepest inside is the centre, about -0.25; the grid corners are outside.
    EXPECT_NEAR(meta["distanceRange"][0].get<double>(), -0.25, 0.02);
    EXPECT_GT(meta["distanceRange"][1].get<double>(), 0.25);

    const RunResult validate = runBake(dir, {"validate", asset.string(), kSphereObj.string()});
    EXPECT_EQ(validate.code, kExitOk) << shown(validate);
    EXPECT_NE(validate.out.find("PASS"), std::string::npos) << validate.out;

    const RunResult validateJson =
        runBake(dir, {"validate", asset.string(), kSphereObj.string(), "--json"});
    ASSERT_EQ(validateJson.code, kExitOk) << shown(validateJson);
    const json report = json::parse(validateJson.out);
    EXPECT_EQ(report["withinLimits"], true);
    EXPECT_EQ(report["sampled"], false);
    EXPECT_EQ(report["sourceHashMatches"], true);
    EXPECT_EQ(report["figures"]["pointsChecked"], 21 * 21 * 21);
    EXPECT_LT(report["figures"]["maxError"].get<double>(), 1e-5);
    EXPECT_EQ(report["figures"]["signMismatches"], 0);
    EXPECT_NEAR(report["figures"]["eikonalMedian"].get<double>(), 1.0, 0.05);

    const fs::path vdb = dir / "sphere.vdb";
    const RunResult exported = runBake(dir, {"export", asset.string(), vdb.string()});
    EXPECT_EQ(exported.code, kExitOk) << shown(exported);
    ASSERT_TRUE(fs::exists(vdb));
    EXPECT_GT(fs::file_size(vdb), 21u * 21 * 21 * 4 / 2);

    // info reads the .vdb back densely: same grid; and it validates like the asset.
    const RunResult vdbInfo = runBake(dir, {"info", vdb.string(), "--json"});
    ASSERT_EQ(vdbInfo.code, kExitOk) << shown(vdbInfo);
    EXPECT_EQ(json::parse(vdbInfo.out)["dims"], json::array({21, 21, 21}));
    const RunResult vdbValidate =
        runBake(dir, {"validate", vdb.string(), kSphereObj.string(), "--json"});
    ASSERT_EQ(vdbValidate.code, kExitOk) << shown(vdbValidate);
    EXPECT_LT(json::parse(vdbValidate.out)["figures"]["maxError"].get<double>(), 1e-5);

    // A level-set .vdb is also a mesh to bake from (its zero isosurface).
    const fs::path fromVdb = dir / "from-vdb.slc";
    const RunResult rebake =
        runBake(dir, {"bake", vdb.string(), "-o", fromVdb.string(), "--resolution", "8", "--json"});
    ASSERT_EQ(rebake.code, kExitOk) << shown(rebake);
    const json rebaked = json::parse(rebake.out);
    EXPECT_EQ(rebaked["asset"]["sourceFile"], "sphere.vdb");
    EXPECT_EQ(rebaked["asset"]["mesh"]["closed"], true);
    EXPECT_TRUE(fs::exists(fromVdb));
}

TEST(Cli, BakingTwiceGivesIdenticalBytes) {
    const fs::path dir = testmesh::tempDir("cli-deterministic");
    const fs::path a = bakeSphere(dir, "a.slc"), b = bakeSphere(dir, "b.slc");
    ASSERT_TRUE(fs::exists(a) && fs::exists(b));
    EXPECT_TRUE(readText(a) == readText(b)) << "two bakes of the same mesh differ";
}

TEST(Cli, ValidateOverTheLimitsExitsOne) {
    const fs::path dir = testmesh::tempDir("cli-over-limits");
    const fs::path good = bakeSphere(dir, "good.slc");
    Result<format::ColliderAsset> asset = format::readAsset(good);
    ASSERT_TRUE(asset.ok()) << asset.error().message();

    // Raise the grid point nearest the surface by half a voxel: max error 0.5 voxel.
    std::size_t nearest = 0;
    for (std::size_t i = 1; i < asset->distances.size(); ++i)
        if (std::abs(asset->distances[i]) < std::abs(asset->distances[nearest]))
            nearest = i;
    asset->distances[nearest] += float(0.5 * asset->meta.voxelSize);
    const fs::path bad = dir / "raised.slc";
    ASSERT_TRUE(format::writeAsset(bad, *asset).ok());

    const RunResult over = runBake(
        dir, {"validate", bad.string(), kSphereObj.string(), "--json", "--max-error", "0.1"});
    EXPECT_EQ(over.code, kExitCheckFailed) << shown(over);
    const json report = json::parse(over.out);
    EXPECT_NEAR(report["figures"]["maxError"].get<double>(), 0.5, 1e-5);
    EXPECT_EQ(report["withinLimits"], false);
    EXPECT_EQ(report["limits"]["maxError"], 0.1);

    const RunResult text = runBake(dir, {"validate", bad.string(), kSphereObj.string()});
    EXPECT_EQ(text.code, kExitCheckFailed) << shown(text);
    EXPECT_NE(text.out.find("FAIL"), std::string::npos) << text.out;
    EXPECT_EQ(
        runBake(dir, {"validate", bad.string(), kSphereObj.string(), "--max-error", "0.6"}).code,
        kExitOk);

    // One sign flipped far from the surface: over the default 0 %, within a 1 % limit.
    Result<format::ColliderAsset> flippedAsset = format::readAsset(good);
    ASSERT_TRUE(flippedAsset.ok());
    flippedAsset->distances[0] = -flippedAsset->distances[0]; // a grid corner, far outside
    const fs::path flipped = dir / "flipped.slc";
    ASSERT_TRUE(format::writeAsset(flipped, *flippedAsset).ok());
    const RunResult signs = runBake(
        dir, {"validate", flipped.string(), kSphereObj.string(), "--json", "--max-error", "100"});
    EXPECT_EQ(signs.code, kExitCheckFailed) << shown(signs);
    EXPECT_EQ(json::parse(signs.out)["figures"]["signMismatches"], 1);
    EXPECT_EQ(runBake(dir, {"validate", flipped.string(), kSphereObj.string(), "--max-error", "100",
                            "--max-sign-errors", "1"})
                  .code,
              kExitOk);
}

TEST(Cli, HalfPrecisionAssetPassesWithItsQuantizationAllowance) {
    const fs::path dir = testmesh::tempDir("cli-f16");
    const fs::path asset = bakeSphere(dir, "half.slc", {"--storage", "f16"});
    const RunResult info = runBake(dir, {"info", asset.string(), "--json"});
    ASSERT_EQ(info.code, kExitOk) << shown(info);
    const json meta = json::parse(info.out);
    EXPECT_EQ(meta["storage"], "f16");
    const double quantization = meta["quantizationError"].get<double>();
    EXPECT_GT(quantization, 0.0);

    const RunResult run = runBake(dir, {"validate", asset.string(), kSphereObj.string(), "--json"});
    EXPECT_EQ(run.code, kExitOk) << shown(run);
    const json report = json::parse(run.out);
    const double voxel = meta["voxelSize"].get<double>();
    EXPECT_LE(report["figures"]["maxError"].get<double>(), quantization / voxel + 1e-5);
    EXPECT_NEAR(report["limits"]["maxError"].get<double>(), 1e-3 + quantization / voxel, 1e-9);
    // A limit tighter than fp16 can hold fails.
    EXPECT_EQ(
        runBake(dir, {"validate", asset.string(), kSphereObj.string(), "--max-error", "1e-7"}).code,
        kExitCheckFailed);
}

TEST(Cli, ValidateWriteStoresTheFiguresInTheAsset) {
    const fs::path dir = testmesh::tempDir("cli-validate-write");
    const fs::path asset = bakeSphere(dir, "sphere.slc");
    const RunResult run =
        runBake(dir, {"validate", asset.string(), kSphereObj.string(), "--write"});
    ASSERT_EQ(run.code, kExitOk) << shown(run);
    const RunResult info = runBake(dir, {"info", asset.string(), "--json"});
    ASSERT_EQ(info.code, kExitOk) << shown(info);
    const json validation = json::parse(info.out)["validation"];
    EXPECT_EQ(validation["known"], true);
    EXPECT_EQ(validation["pointsChecked"], kSpherePoints);
    EXPECT_EQ(validation["signMismatches"], 0);
    EXPECT_NEAR(validation["eikonalMedian"].get<double>(), 1.0, 0.05);
    EXPECT_NE(runBake(dir, {"info", asset.string()}).out.find("validation    "), std::string::npos);
}

TEST(Cli, BadMeshesExitTwoNamingTheFileAndWriteNothing) {
    const fs::path dir = testmesh::tempDir("cli-bad-mesh");
    const fs::path empty = dir / "empty.obj";
    std::ofstream(empty).close();
    const fs::path garbage = dir / "garbage.stl";
    std::ofstream(garbage) << "solid nothing\nthis is not an stl file\n";
    std::vector<fs::path> meshes = {empty, garbage, dir / "missing.obj"};
    const fs::path models = SLUICE_ASSIMP_MODELS;
    for (const char* name : {"invalid/empty.off", "invalid/empty.ply", "invalid/malformed.obj",
                             "OBJ/point_cloud.obj", "OBJ/testline.obj"})
        if (fs::exists(models / name))
            meshes.push_back(models / name);

    const fs::path output = dir / "out" / "collider.slc";
    fs::create_directories(output.parent_path());
    for (const fs::path& mesh : meshes) {
        SCOPED_TRACE(mesh.string());
        fs::remove(output);
        expectRejected(dir, {"bake", mesh.string(), "-o", output.string()},
                       mesh.filename().string(), output);
        // A previous OUT stays byte for byte what it was.
        std::ofstream(output) << "previous asset bytes";
        expectRejected(dir, {"bake", mesh.string(), "-o", output.string()},
                       mesh.filename().string(), output);
        EXPECT_EQ(readText(output), "previous asset bytes");
    }
}

TEST(Cli, BadGridArgumentsExitTwoAndWriteNothing) {
    const fs::path dir = testmesh::tempDir("cli-bad-grid");
    const fs::path output = dir / "out" / "collider.slc";
    fs::create_directories(output.parent_path());
    const std::string mesh = kSphereObj.string();
    expectRejected(dir, {"bake", mesh, "-o", output.string(), "--resolution", "0"}, "--resolution",
                   output);
    expectRejected(dir, {"bake", mesh, "-o", output.string(), "--voxel-size=-1"}, "--voxel-size",
                   output);
    expectRejected(dir, {"bake", mesh, "-o", output.string(), "--voxel-size", "-1"}, "--voxel-size",
                   output);
    expectRejected(
        dir, {"bake", mesh, "-o", output.string(), "--resolution", "8", "--voxel-size", "0.1"},
        "--voxel-size", output);
    expectRejected(dir, {"bake", mesh, "-o", output.string(), "--scale", "0"}, "--scale", output);
    expectRejected(dir, {"bake", mesh, "-o", output.string(), "--sign", "majority"}, "majority",
                   output);
    expectRejected(dir, {"bake", mesh, "-o", output.string(), "--storage", "f64"}, "f64", output);
    expectRejected(dir, {"bake", mesh, "-o", output.string(), "--backend", "magic"}, "magic",
                   output);
    // A folder that cannot be created (a file stands in its way) is reported before any work.
    std::ofstream(dir / "a-file") << "not a folder";
    const fs::path nowhere = dir / "a-file" / "x.slc";
    expectRejected(dir, {"bake", mesh, "-o", nowhere.string()}, "cannot create the folder",
                   nowhere);
}

TEST(Cli, BakeCreatesTheOutputsFolder) {
    const fs::path dir = testmesh::tempDir("cli-bake-creates-folder");
    const fs::path output = bakeSphere(dir, "new/deeper/collider.slc");
    EXPECT_TRUE(format::readAsset(output).ok()) << output;
}

TEST(Cli, BakeWarnsWhenTheOutputDoesNotEndInSlc) {
    const fs::path dir = testmesh::tempDir("cli-bake-extension");
    const fs::path output = dir / "r.png";
    const RunResult run = runBake(dir, {"bake", kSphereObj.string(), "-o", output.string(),
                                        "--resolution", "8", "--backend", "cgal", "--quiet"});
    EXPECT_EQ(run.code, kExitOk) << shown(run);
    EXPECT_EQ(run.err, "sluice-bake bake: warning: '" + output.string() +
                           "' does not end in .slc; it will hold a collider asset all the same\n");
    EXPECT_TRUE(format::readAsset(output).ok());
    const RunResult slc = runBake(dir, {"bake", kSphereObj.string(), "-o", (dir / "r.SLC").string(),
                                        "--resolution", "8", "--backend", "cgal", "--quiet"});
    EXPECT_EQ(slc.code, kExitOk) << shown(slc);
    EXPECT_EQ(slc.err, "");
}

TEST(Cli, BakeSummaryShowsTheMeshBoxAndTheVoxelSize) {
    const fs::path dir = testmesh::tempDir("cli-bake-summary");
    const RunResult run = runBake(dir, {"bake", kSphereObj.string(), "-o", (dir / "s.slc").string(),
                                        "--resolution", "16", "--backend", "cgal"});
    ASSERT_EQ(run.code, kExitOk) << shown(run);
    // The demo sphere has radius 0.25: a 0.5 box, 16 voxels across it.
    EXPECT_NE(run.out.find("\n  mesh box 0.5 x 0.5 x 0.5 world units\n"), std::string::npos)
        << run.out;
    EXPECT_NE(run.out.find("voxel size 0.03125 world units\n"), std::string::npos) << run.out;
    EXPECT_NE(run.out.find("1280 triangles, 642 vertices"), std::string::npos) << run.out;
}

TEST(Cli, OneOfAThingIsSingularInTheSummary) {
    const fs::path dir = testmesh::tempDir("cli-bake-singular");
    std::ofstream(dir / "tri.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    const RunResult run =
        runBake(dir, {"bake", (dir / "tri.obj").string(), "-o", (dir / "tri.slc").string(),
                      "--resolution", "4", "--backend", "cgal"});
    ASSERT_EQ(run.code, kExitOk) << shown(run);
    EXPECT_NE(run.out.find("  mesh     1 triangle, 3 vertices, open"), std::string::npos)
        << run.out;
    EXPECT_NE(run.out.find(", 3 boundary edges, 0 non-manifold edges\n"), std::string::npos)
        << run.out;
}

TEST(Cli, ExportOfAVdbSaysItIsAlreadyOne) {
    const fs::path dir = testmesh::tempDir("cli-export-vdb");
    const fs::path vdb = dir / "x.vdb";
    std::ofstream(vdb) << "anything";
    const RunResult run = runBake(dir, {"export", vdb.string(), (dir / "y.vdb").string()});
    EXPECT_EQ(run.code, kExitBadInput) << shown(run);
    EXPECT_EQ(run.err, "sluice-bake export: '" + vdb.string() +
                           "' is already a .vdb file (export converts a collider asset, .slc, to "
                           "OpenVDB)\n");
    EXPECT_FALSE(fs::exists(dir / "y.vdb"));
}

TEST(Cli, InfoPngAndExportCreateTheirOutputFolders) {
    const fs::path dir = testmesh::tempDir("cli-output-folders");
    const fs::path asset = bakeSphere(dir, "s.slc");
    const fs::path png = dir / "pictures" / "z" / "s.png";
    RunResult run =
        runBake(dir, {"info", asset.string(), "--slice", "z=0.5", "--png", png.string()});
    EXPECT_EQ(run.code, kExitOk) << shown(run);
    EXPECT_TRUE(fs::is_regular_file(png));
    const fs::path vdb = dir / "vdb" / "out" / "s.vdb";
    run = runBake(dir, {"export", asset.string(), vdb.string(), "--quiet"});
    EXPECT_EQ(run.code, kExitOk) << shown(run);
    EXPECT_TRUE(fs::is_regular_file(vdb));
    // A folder given as the output is refused before anything is read.
    fs::create_directories(dir / "folder.vdb");
    run = runBake(dir, {"export", asset.string(), (dir / "folder.vdb").string()});
    EXPECT_EQ(run.code, kExitBadInput) << shown(run);
    EXPECT_NE(run.err.find("folder.vdb' is a folder, not a file"), std::string::npos) << run.err;
}

TEST(Cli, InfoOfAVdbShowsItsProvenanceAndNullForWhatItDoesNotRecord) {
    const fs::path dir = testmesh::tempDir("cli-info-vdb");
    const fs::path asset = bakeSphere(dir, "s.slc", {"--backend", "cgal"});
    const fs::path vdb = dir / "s.vdb";
    ASSERT_EQ(runBake(dir, {"export", asset.string(), vdb.string(), "--quiet"}).code, kExitOk);

    const RunResult text = runBake(dir, {"info", vdb.string()});
    ASSERT_EQ(text.code, kExitOk) << shown(text);
    EXPECT_NE(text.out.find("\n  source        sphere.obj  (xxh3 "), std::string::npos) << text.out;
    EXPECT_NE(text.out.find("\n  tool          sluice-bake "), std::string::npos) << text.out;
    EXPECT_NE(text.out.find("\n  bake          backend cgal, sign parity"), std::string::npos)
        << text.out;

    const RunResult js = runBake(dir, {"info", vdb.string(), "--json"});
    ASSERT_EQ(js.code, kExitOk) << shown(js);
    const json info = json::parse(js.out);
    EXPECT_TRUE(info["header"].is_null());
    EXPECT_EQ(info["sourceFile"], "sphere.obj");
    EXPECT_EQ(info["bake"]["backend"], "cgal");
    EXPECT_TRUE(info["bake"]["resolution"].is_null());
    EXPECT_TRUE(info["bake"]["padding"].is_null());
    EXPECT_TRUE(info["mesh"]["triangles"].is_null());
    EXPECT_TRUE(info["mesh"]["closed"].is_null());
    EXPECT_EQ(info["validation"]["known"], false);
    EXPECT_TRUE(info["validation"]["maxError"].is_null());
}

TEST(Cli, CorruptedAssetsExitTwoNamingTheError) {
    const fs::path dir = testmesh::tempDir("cli-corrupt");
    const fs::path good = bakeSphere(dir, "good.slc");
    const std::string bytes = readText(good);
    ASSERT_GT(bytes.size(), format::kAssetHeaderSize + 16);

    struct Case {
        const char* name;
        std::string bytes;
        const char* error;
    };
    std::string flipped = bytes;
    flipped[bytes.size() - 3] = char(flipped[bytes.size() - 3] ^ 0x40);
    std::string magic = bytes;
    magic[1] = 'X';
    const Case cases[] = {{"checksum.slc", flipped, "ChecksumMismatch"},
                          {"truncated.slc", bytes.substr(0, bytes.size() - 100), "Truncated"},
                          {"magic.slc", magic, "BadMagic"},
                          {"empty.slc", std::string(), "Truncated"}};
    for (const Case& c : cases) {
        SCOPED_TRACE(c.name);
        const fs::path path = dir / c.name;
        std::ofstream(path, std::ios::binary) << c.bytes;
        const RunResult info = runBake(dir, {"info", path.string()});
        EXPECT_EQ(info.code, kExitBadInput) << shown(info);
        EXPECT_NE(info.err.find(c.error), std::string::npos) << info.err;
        EXPECT_NE(info.err.find(c.name), std::string::npos) << info.err;
        const RunResult validate = runBake(dir, {"validate", path.string(), kSphereObj.string()});
        EXPECT_EQ(validate.code, kExitBadInput) << shown(validate);
        EXPECT_NE(validate.err.find(c.error), std::string::npos) << validate.err;
        const fs::path vdb = dir / "out.vdb";
        const RunResult exported = runBake(dir, {"export", path.string(), vdb.string()});
        EXPECT_EQ(exported.code, kExitBadInput) << shown(exported);
        EXPECT_FALSE(fs::exists(vdb));
    }
    const RunResult missing = runBake(dir, {"info", (dir / "missing.slc").string()});
    EXPECT_EQ(missing.code, kExitBadInput) << shown(missing);
    EXPECT_NE(missing.err.find("missing.slc"), std::string::npos) << missing.err;

    // validate also refuses an unreadable mesh.
    const RunResult badMesh =
        runBake(dir, {"validate", good.string(), (dir / "nope.obj").string()});
    EXPECT_EQ(badMesh.code, kExitBadInput) << shown(badMesh);
    EXPECT_NE(badMesh.err.find("nope.obj"), std::string::npos) << badMesh.err;
}

TEST(Cli, InfoSliceWritesAPng) {
    const fs::path dir = testmesh::tempDir("cli-slice");
    const fs::path asset = bakeSphere(dir, "sphere.slc");
    const fs::path png = dir / "slice.png";
    const RunResult run =
        runBake(dir, {"info", asset.string(), "--slice", "z=0.5", "--png", png.string()});
    ASSERT_EQ(run.code, kExitOk) << shown(run);
    ASSERT_TRUE(fs::exists(png));
    EXPECT_EQ(readText(png).substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));

    EXPECT_EQ(runBake(dir, {"info", asset.string(), "--slice", "w=2", "--png",
                            (dir / "bad.png").string()})
                  .code,
              kExitBadInput);
    EXPECT_FALSE(fs::exists(dir / "bad.png"));
    EXPECT_EQ(runBake(dir, {"info", asset.string(), "--slice", "z=0.5"}).code, kExitBadInput);
}

} // namespace
} // namespace sluice::bake
