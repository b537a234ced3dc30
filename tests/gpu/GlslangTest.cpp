// Every shader program, as the programs assemble it, through the Khronos reference compiler.
//
// Mesa compiles and runs every shader in the other tests; glslangValidator (Debian glslang-tools)
// checks the same text against the GLSL 4.50 specification, so what Mesa tolerates and a stricter
// driver rejects fails here. Each case takes the embedded source (shared headers inlined, exactly
// the string the program passes to the driver), adds its defines with assembleShaderSource, and
// validates it; a graphics program's two stages are also linked, which checks their interface.
#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <ostream>
#include <set>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include <gtest/gtest.h>

#include "ProgramRun.h"
#include "sluice/bake/BakeShaders.h"
#include "sluice/gpu/GpuShaders.h"
#include "sluice/gpu/Program.h"
#include "sluice/rt/RuntimeShaders.h"
#include "support/TempDir.h"

namespace sluice::gpu {
namespace {

/// One program as the code builds it: its stages' embedded file names and its defines.
struct ProgramCase {
    const char* name;                             ///< test name suffix
    std::string_view (*source)(std::string_view); ///< the library's embedded-shader lookup
    std::vector<std::string> stages;   ///< file names, one per stage (extension gives the stage)
    std::vector<ShaderDefine> defines; ///< as passed to Program::compute / Program::graphics
};

/// What gtest prints for a case: its name.
void PrintTo(const ProgramCase& program, std::ostream* out) {
    *out << program.name;
}

std::string_view gpuSource(std::string_view name) {
    return gpu::shaders::shaderSource(name);
}
std::string_view runtimeSource(std::string_view name) {
    return rt::shaders::shaderSource(name);
}
std::string_view bakeSource(std::string_view name) {
    return bake::shaders::shaderSource(name);
}

ProgramCase compute(const char* name, decltype(ProgramCase::source) source, const char* file,
                    std::vector<ShaderDefine> defines = {}) {
    return {name, source, {file}, std::move(defines)};
}

ProgramCase graphics(const char* name, const char* vertex, const char* fragment,
                     std::vector<ShaderDefine> defines = {}) {
    return {name, runtimeSource, {vertex, fragment}, std::move(defines)};
}

const ShaderDefine kSparse{"SLUICE_SPARSE_COLLIDERS", "1"};
const ShaderDefine kSdfStorage{"SLUICE_SDF_STORAGE", "1"};
const ShaderDefine kNeighboursStorage{"SLUICE_NEIGHBOURS_STORAGE", "1"};
const ShaderDefine kSparseBake{"SDF_SPARSE", "1"};
const ShaderDefine kPointsBake{"SDF_POINTS", "1"};

// The solver's passes (Simulation.cpp, VolumeMaps.cpp, PrefixScan.cpp, SelfTest.cpp and the
// probes).
std::vector<ProgramCase> solverPrograms() {
    return {
        compute("GpuSelfTest", gpuSource, "gpu_selftest.comp"),
        compute("PbfPredict", runtimeSource, "pbf_predict.comp"),
        compute("PbfScatter", runtimeSource, "pbf_scatter.comp"),
        compute("PbfBucketSort", runtimeSource, "pbf_bucket_sort.comp"),
        compute("PbfReorder", runtimeSource, "pbf_reorder.comp"),
        compute("PbfScatterReorder", runtimeSource, "pbf_reorder.comp",
                {{"PBF_SCATTER_REORDER", "1"}}),
        compute("PbfLambda", runtimeSource, "pbf_lambda.comp"),
        compute("PbfDelta", runtimeSource, "pbf_delta.comp"),
        compute("PbfVorticity", runtimeSource, "pbf_vorticity.comp"),
        compute("PbfConfine", runtimeSource, "pbf_confine.comp"),
        compute("PbfStats", runtimeSource, "pbf_stats.comp"),
        compute("PbfBodies", runtimeSource, "pbf_bodies.comp"),
        // A scene with a sparse collider compiles every pass with NanoVDB's GLSL reader.
        compute("PbfLambdaSparse", runtimeSource, "pbf_lambda.comp", {kSparse}),
        compute("PbfDeltaSparse", runtimeSource, "pbf_delta.comp", {kSparse}),
        compute("PbfStatsSparse", runtimeSource, "pbf_stats.comp", {kSparse}),
        compute("PbfBodiesSparse", runtimeSource, "pbf_bodies.comp", {kSparse}),
        // Grids past the GL's texel-buffer limit are read from the storage block instead.
        compute("PbfLambdaSdfStorage", runtimeSource, "pbf_lambda.comp", {kSdfStorage}),
        compute("PbfDeltaSdfStorage", runtimeSource, "pbf_delta.comp", {kSparse, kSdfStorage}),
        compute("PbfBodiesSdfStorage", runtimeSource, "pbf_bodies.comp", {kSdfStorage}),
        compute("PbfVolumeMapSdfStorage", runtimeSource, "pbf_volume_map.comp", {kSdfStorage}),
        compute("PbfStatsSdfStorage", runtimeSource, "pbf_stats.comp", {kSdfStorage}),
        compute("PbfBoundaryProbeSdfStorage", runtimeSource, "pbf_boundary_probe.comp",
                {kSdfStorage}),
        compute("ColliderProbeSdfStorage", runtimeSource, "collider_probe.comp",
                {kSparse, kSdfStorage}),
        // Particle buffers past the GL's texel-buffer limit: the neighbour passes read storage.
        compute("PbfLambdaNeighboursStorage", runtimeSource, "pbf_lambda.comp",
                {kNeighboursStorage}),
        compute("PbfDeltaNeighboursStorage", runtimeSource, "pbf_delta.comp",
                {kSparse, kNeighboursStorage}),
        compute("PbfVorticityNeighboursStorage", runtimeSource, "pbf_vorticity.comp",
                {kNeighboursStorage}),
        compute("PbfConfineNeighboursStorage", runtimeSource, "pbf_confine.comp",
                {kNeighboursStorage}),
        compute("PbfVolumeMap", runtimeSource, "pbf_volume_map.comp"),
        compute("PbfVolumeMapSparse", runtimeSource, "pbf_volume_map.comp", {kSparse}),
        compute("PbfBoundaryProbe", runtimeSource, "pbf_boundary_probe.comp"),
        compute("PbfColliderForces", runtimeSource, "pbf_collider_forces.comp"),
        compute("PbfColliderForcesSparse", runtimeSource, "pbf_collider_forces.comp", {kSparse}),
        compute("PbfColliderForcesSdfStorage", runtimeSource, "pbf_collider_forces.comp",
                {kSdfStorage}),
        compute("PbfBoundaryProbeSparse", runtimeSource, "pbf_boundary_probe.comp", {kSparse}),
        compute("PbfCopyById", runtimeSource, "pbf_copy_by_id.comp"),
        compute("ColliderProbe", runtimeSource, "collider_probe.comp"),
        compute("ColliderProbeSparse", runtimeSource, "collider_probe.comp", {kSparse}),
        compute("ScanBlock", runtimeSource, "scan_block.comp"),
        compute("ScanAdd", runtimeSource, "scan_add.comp"),
    };
}

// The renderer's passes (Renderer.cpp, FluidSurfacePass.cpp, SphereSplatPass.cpp,
// ColliderPass.cpp).
std::vector<ProgramCase> renderPrograms() {
    return {
        compute("RenderStats", runtimeSource, "render_stats.comp"),
        graphics("RenderParticles", "render_particles.vert", "render_particles.frag"),
        graphics("RenderParticlesFluidDepth", "render_particles.vert", "render_particles.frag",
                 {{"SLUICE_FLUID_DEPTH", "1"}}),
        graphics("RenderParticlesThickness", "render_particles.vert", "render_particles.frag",
                 {{"SLUICE_THICKNESS", "1"}}),
        graphics("RenderParticlesListed", "render_particles.vert", "render_particles.frag",
                 {{"SLUICE_PARTICLE_LIST", "1"}}),
        compute("RenderSplat", runtimeSource, "render_splat.comp"),
        compute("RenderSplatWinner", runtimeSource, "render_splat.comp",
                {{"SLUICE_SPLAT_WINNER", "1"}}),
        compute("RenderSplatThickness", runtimeSource, "render_splat.comp",
                {{"SLUICE_SPLAT_THICKNESS", "1"}}),
        graphics("RenderSplatResolve", "render_fullscreen.vert", "render_splat_resolve.frag"),
        graphics("RenderSplatFluidDepth", "render_fullscreen.vert", "render_splat_fluid.frag"),
        graphics("RenderSplatFluidThickness", "render_fullscreen.vert", "render_splat_fluid.frag",
                 {{"SLUICE_THICKNESS", "1"}}),
        graphics("RenderParticlesFluidDepthListed", "render_particles.vert",
                 "render_particles.frag",
                 {{"SLUICE_FLUID_DEPTH", "1"}, {"SLUICE_PARTICLE_LIST", "1"}}),
        graphics("RenderParticlesThicknessListed", "render_particles.vert", "render_particles.frag",
                 {{"SLUICE_THICKNESS", "1"}, {"SLUICE_PARTICLE_LIST", "1"}}),
        graphics("RenderBackdrop", "render_fullscreen.vert", "render_backdrop.frag"),
        graphics("RenderDomainBox", "render_domain_box.vert", "render_domain_box.frag"),
        graphics("RenderSurfaceMesh", "render_surface_mesh.vert", "render_surface_mesh.frag"),
        compute("RenderFluidSmooth", runtimeSource, "render_fluid_smooth.comp"),
        graphics("RenderFluidComposite", "render_fullscreen.vert", "render_fluid_composite.frag"),
        graphics("RenderCollider", "render_collider.vert", "render_collider.frag"),
        graphics("RenderColliderGlass", "render_collider.vert", "render_collider.frag",
                 {{"SLUICE_GLASS", "1"}}),
        graphics("RenderColliderSparse", "render_collider.vert", "render_collider.frag", {kSparse}),
        graphics("RenderColliderGlassSparse", "render_collider.vert", "render_collider.frag",
                 {{"SLUICE_GLASS", "1"}, kSparse}),
    };
}

// The surface reconstruction's passes (SurfaceReconstructor.cpp).
std::vector<ProgramCase> surfacePrograms() {
    return {
        compute("SurfaceBounds", runtimeSource, "surface_bounds.comp"),
        compute("SurfaceMark", runtimeSource, "surface_mark.comp"),
        compute("SurfaceCompact", runtimeSource, "surface_compact.comp"),
        compute("SurfaceSplat", runtimeSource, "surface_splat.comp"),
        compute("SurfaceDeposit", runtimeSource, "surface_deposit.comp"),
        compute("SurfaceDensity", runtimeSource, "surface_density.comp"),
        compute("SurfaceBlur", runtimeSource, "surface_blur.comp"),
        compute("SurfaceBinCount", runtimeSource, "surface_bin_count.comp"),
        compute("SurfaceBinFill", runtimeSource, "surface_bin_fill.comp"),
        compute("SurfaceAnisotropy", runtimeSource, "surface_anisotropy.comp"),
        compute("SurfaceCount", runtimeSource, "surface_count.comp"),
        compute("SurfaceVertices", runtimeSource, "surface_vertices.comp"),
        compute("SurfaceTriangles", runtimeSource, "surface_triangles.comp"),
    };
}

// The GPU baker's passes (GpuBaker.cpp, compilePrograms).
std::vector<ProgramCase> bakePrograms() {
    return {
        compute("SdfCoarse", bakeSource, "sdf_coarse.comp"),
        compute("SdfDistance", bakeSource, "sdf_distance.comp"),
        compute("SdfSign", bakeSource, "sdf_sign.comp"),
        compute("SdfSignCoarse", bakeSource, "sdf_sign.comp", {{"SDF_SIGN_COARSE", "1"}}),
        compute("SdfSignExact", bakeSource, "sdf_sign.comp", {{"SDF_SIGN_EXACT", "1"}}),
        compute("SdfCoarseSparse", bakeSource, "sdf_coarse.comp", {kSparseBake}),
        compute("SdfDistanceSparse", bakeSource, "sdf_distance.comp", {kSparseBake}),
        compute("SdfSignSparse", bakeSource, "sdf_sign.comp", {kSparseBake}),
        compute("SdfSignCoarseSparse", bakeSource, "sdf_sign.comp",
                {{"SDF_SIGN_COARSE", "1"}, kSparseBake}),
        compute("SdfSignExactSparse", bakeSource, "sdf_sign.comp",
                {{"SDF_SIGN_EXACT", "1"}, kSparseBake}),
        compute("SdfCoarsePoints", bakeSource, "sdf_coarse.comp", {kPointsBake}),
        compute("SdfSignCoarsePoints", bakeSource, "sdf_sign.comp",
                {{"SDF_SIGN_COARSE", "1"}, kPointsBake}),
    };
}

/// Every program the libraries build, with the define combinations their code uses:
/// SelfTest.cpp, Simulation.cpp, VolumeMaps.cpp, PrefixScan.cpp, SparseSamplerParityTest.cpp,
/// FluidStatsProbe.cpp, Renderer.cpp, FluidSurfacePass.cpp, SphereSplatPass.cpp, ColliderPass.cpp,
/// SurfaceReconstructor.cpp and GpuBaker.cpp (compilePrograms).
std::vector<ProgramCase> allPrograms() {
    std::vector<ProgramCase> all;
    for (auto part : {solverPrograms, renderPrograms, surfacePrograms, bakePrograms})
        for (ProgramCase& c : part())
            all.push_back(std::move(c));
    return all;
}

/// Writes one stage's text where glslangValidator reads it; false if it could not.
bool writeStage(const std::filesystem::path& path, const std::string& text) {
    std::ofstream out(path, std::ios::binary);
    out << text;
    return out.good();
}

class ReferenceCompiler : public ::testing::TestWithParam<ProgramCase> {};

TEST_P(ReferenceCompiler, AcceptsTheProgramAsAssembled) {
    const std::string validator = SLUICE_GLSLANG_VALIDATOR;
    ASSERT_FALSE(validator.empty())
        << "glslangValidator was not found when the build was configured: install Debian's "
           "glslang-tools (bash cmake/setup.sh test does) and configure again";
    const ProgramCase& program = GetParam();
    test::TempDir dir;
    std::vector<std::string> args;
    if (program.stages.size() > 1)
        args.push_back("-l"); // link the stages: their interfaces must match
    for (const std::string& stage : program.stages) {
        const std::string_view source = program.source(stage);
        ASSERT_FALSE(source.empty()) << stage << " is not embedded in the library that builds it";
        const std::filesystem::path path = dir / stage;
        ASSERT_TRUE(writeStage(path, assembleShaderSource(source, program.defines)))
            << "cannot write " << path;
        args.push_back(path.string());
    }
    const testrun::RunResult run = testrun::runProgram(validator, dir.path(), args);
    EXPECT_EQ(run.code, 0) << testrun::shown(run);
}

/// Storage blocks one compute program may use at most. GL 4.5 guarantees 8 per stage; the
/// solver's passes need more, and 16 is what Mesa (llvmpipe included) and NVIDIA's driver give a
/// compute shader (`sluice-bake gl-info` prints it). Checked here for every define combination
/// without a GL, so a pass that grows past it fails before a driver refuses to link it.
constexpr int kStorageBlocksMost = 16;

/// The names of the storage blocks ("buffer Name {") declared in a GLSL text. (Scanned by
/// hand: GCC 12's std::regex trips -Wmaybe-uninitialized in the ASan build.)
std::set<std::string> storageBlockNames(std::string_view text) {
    const auto word = [](char c) {
        return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
    };
    const auto space = [](char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; };
    std::set<std::string> names;
    const std::string_view keyword = "buffer";
    for (std::size_t at = text.find(keyword); at != std::string_view::npos;
         at = text.find(keyword, at + 1)) {
        std::size_t p = at + keyword.size();
        if ((at > 0 && word(text[at - 1])) || p >= text.size() || !space(text[p]))
            continue;
        while (p < text.size() && space(text[p]))
            ++p;
        const std::size_t nameBegin = p;
        while (p < text.size() && word(text[p]))
            ++p;
        const std::size_t nameEnd = p;
        while (p < text.size() && space(text[p]))
            ++p;
        if (nameEnd > nameBegin && p < text.size() && text[p] == '{')
            names.emplace(text.substr(nameBegin, nameEnd - nameBegin));
    }
    return names;
}

// The reference compiler's reflection lists the blocks a program uses (the unused ones are left
// out, as a driver leaves them inactive); this glslang lists storage blocks among the uniform
// blocks, so they are picked out by the names the text declares with `buffer`.
class ComputeStorageBlocks : public ::testing::TestWithParam<ProgramCase> {};

TEST_P(ComputeStorageBlocks, AreAtMostSixteen) {
    const ProgramCase& program = GetParam();
    const std::string validator = SLUICE_GLSLANG_VALIDATOR;
    ASSERT_FALSE(validator.empty()) << "glslangValidator was not found when the build was "
                                       "configured: install Debian's glslang-tools";
    test::TempDir dir;
    const std::string text =
        assembleShaderSource(program.source(program.stages[0]), program.defines);
    const std::filesystem::path path = dir / program.stages[0];
    ASSERT_TRUE(writeStage(path, text)) << "cannot write " << path;
    const testrun::RunResult run =
        testrun::runProgram(validator, dir.path(), {"-l", "-q", path.string()});
    ASSERT_EQ(run.code, 0) << testrun::shown(run);
    const std::set<std::string> declared = storageBlockNames(text);
    std::istringstream lines(run.out);
    std::string line;
    bool inBlocks = false;
    std::vector<std::string> used;
    while (std::getline(lines, line)) {
        if (line.empty()) {
            inBlocks = false;
        } else if (line.ends_with("block reflection:")) {
            inBlocks = true;
        } else if (inBlocks) {
            const std::string name = line.substr(0, line.find(':'));
            if (declared.count(name))
                used.push_back(name);
        }
    }
    ASSERT_NE(run.out.find("block reflection:"), std::string::npos)
        << "no block reflection in the compiler's output:\n"
        << run.out;
    EXPECT_LE(int(used.size()), kStorageBlocksMost) << ::testing::PrintToString(used);
}

std::string caseName(const ::testing::TestParamInfo<ProgramCase>& param) {
    return param.param.name;
}

INSTANTIATE_TEST_SUITE_P(EveryProgram, ReferenceCompiler, ::testing::ValuesIn(allPrograms()),
                         caseName);

/// The compute programs of allPrograms() (one stage each).
std::vector<ProgramCase> computePrograms() {
    std::vector<ProgramCase> compute = allPrograms();
    std::erase_if(compute, [](const ProgramCase& program) { return program.stages.size() != 1; });
    return compute;
}

INSTANTIATE_TEST_SUITE_P(EveryComputeProgram, ComputeStorageBlocks,
                         ::testing::ValuesIn(computePrograms()), caseName);

TEST(ReferenceCompilerCases, CoverEveryShaderFile) {
    std::set<std::string> covered;
    for (const ProgramCase& program : allPrograms())
        covered.insert(program.stages.begin(), program.stages.end());
    for (const auto& entry : std::filesystem::directory_iterator(SLUICE_SHADER_DIR)) {
        const std::string ext = entry.path().extension().string();
        if (ext == ".comp" || ext == ".vert" || ext == ".frag") {
            EXPECT_TRUE(covered.count(entry.path().filename().string()))
                << entry.path().filename() << " has no case in GlslangTest.cpp";
        }
    }
}

} // namespace
} // namespace sluice::gpu
