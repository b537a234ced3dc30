// `sluice-bake gl-info`: which headless OpenGL 4.5 context this machine gives, and its limits.
#include <iostream>

#include "commands/CliSupport.h"
#include "sluice/bake/commands/Cli.h"
#include "sluice/gpu/Context.h"

namespace sluice::bake::cli {
namespace {

struct GlInfoArgs {
    bool json = false;
    std::string platform;
    int device = -1;
    bool selfTest = false;
};

nlohmann::ordered_json toJson(const gpu::ContextInfo& info) {
    nlohmann::ordered_json out = {
        {"vendor", info.vendor},
        {"renderer", info.renderer},
        {"glVersion", info.glVersion},
        {"glslVersion", info.glslVersion},
        {"glMajor", info.glMajor},
        {"glMinor", info.glMinor},
        {"platform", info.platform},
        {"deviceIndex", info.deviceIndex},
        {"deviceName", info.deviceName},
        {"eglVersion", info.eglVersion},
        {"debug", info.debug},
        {"maxWorkGroupCount",
         {info.maxWorkGroupCount.x, info.maxWorkGroupCount.y, info.maxWorkGroupCount.z}},
        {"maxWorkGroupSize",
         {info.maxWorkGroupSize.x, info.maxWorkGroupSize.y, info.maxWorkGroupSize.z}},
        {"maxWorkGroupInvocations", info.maxWorkGroupInvocations},
        {"maxSharedMemoryBytes", info.maxSharedMemoryBytes},
        {"maxSsboBytes", info.maxSsboBytes},
        {"maxSsboBindings", info.maxSsboBindings},
        {"max3DTextureSize", info.max3DTextureSize},
        {"gpuMemoryTotalBytes", nullptr},
        {"gpuMemoryAvailableBytes", nullptr}};
    if (info.gpuMemoryTotalBytes)
        out["gpuMemoryTotalBytes"] = *info.gpuMemoryTotalBytes;
    if (info.gpuMemoryAvailableBytes)
        out["gpuMemoryAvailableBytes"] = *info.gpuMemoryAvailableBytes;
    return out;
}

int runGlInfo(const GlInfoArgs& args) {
    constexpr std::string_view cmd = "gl-info";
    gpu::ContextOptions options;
    options.platform = args.platform;
    options.deviceIndex = args.device;
    Result<gpu::Context> context = gpu::Context::createHeadless(options);
    if (!context)
        return reportError(cmd, "headless context", context.error());
    if (args.selfTest)
        if (Result<void> ok = context->selfTest(); !ok)
            return reportError(cmd,
                               "the compute self-test failed on '" + context->info().renderer + "'",
                               ok.error());

    const gpu::ContextInfo& info = context->info();
    if (args.json) {
        nlohmann::ordered_json out = toJson(info);
        out["selfTest"] =
            args.selfTest ? nlohmann::ordered_json("passed") : nlohmann::ordered_json(nullptr);
        std::cout << out.dump(2) << '\n';
    } else {
        std::cout << info.describe();
        if (!info.describe().empty() && info.describe().back() != '\n')
            std::cout << '\n';
        if (args.selfTest)
            std::cout << "compute self-test: passed\n";
    }
    return kExitOk;
}

/// The options of `gl-info`, bound to `args`.
void addGlInfoOptions(CLI::App& app, GlInfoArgs& args) {
    app.add_flag("--json", args.json, "print as JSON");
    app.add_option("--platform", args.platform,
                   "EGL platform: auto, device or surfaceless (default: SLUICE_EGL_PLATFORM, "
                   "else auto)");
    app.add_option("--device", args.device,
                   "EGL device index on the device platform (default: SLUICE_EGL_DEVICE, else "
                   "every device, GPUs first)");
    app.add_flag("--self-test", args.selfTest,
                 "also run a compute shader and compare it with the CPU");
}

} // namespace

Command addGlInfoCommand(CLI::App& parent) {
    return addSubcommand(
        parent, "gl-info",
        "Create the headless OpenGL 4.5 context (EGL) and print what it runs on and "
        "its compute limits. Exit 3 if there is none.",
        addGlInfoOptions, runGlInfo);
}

} // namespace sluice::bake::cli
