// runCli: the sluice-bake command line (CLI11), its subcommands and its exit codes.
#include "sluice/bake/commands/Cli.h"

#include <exception>
#include <iostream>
#include <vector>

#include "commands/CliSupport.h"

namespace sluice::bake {
namespace {

constexpr const char* kExitCodeHelp = R"(Exit codes:
  0  success (validate: within the limits)
  1  validate: over --max-error or --max-sign-errors
  2  bad input: a file, mesh, asset or command-line value (nothing is written)
  3  no OpenGL 4.5 core context with compute shaders
  4  internal error)";

int run(int argc, char** argv) {
    CLI::App app{"sluice-bake: bakes meshes into signed-distance-field collider assets (.slc), "
                 "checks them against the exact CGAL reference, converts them to OpenVDB, "
                 "and turns particle frames into OpenVDB level sets.",
                 "sluice-bake"};
    app.set_version_flag("--version", cli::toolVersion());
    app.require_subcommand(1);
    app.footer(kExitCodeHelp);

    const std::vector<cli::Command> commands = {
        cli::addBakeCommand(app),    cli::addValidateCommand(app), cli::addInfoCommand(app),
        cli::addExportCommand(app),  cli::addGlInfoCommand(app),   cli::addBatchCommand(app),
        cli::addSurfaceCommand(app),
    };

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        // --help and --version arrive here too, and exit 0.
        return format::cli::reportParseError(app, e, "sluice-bake", kExitBadInput);
    }

    for (const cli::Command& command : commands)
        if (command.app->parsed())
            return command.run();
    return kExitInternal; // require_subcommand(1) makes this unreachable
}

} // namespace

int runCli(int argc, char** argv) {
    try {
        return run(argc, argv);
    } catch (const std::exception& e) {
        std::cerr << "sluice-bake: internal error: " << e.what() << '\n';
    } catch (...) {
        std::cerr << "sluice-bake: internal error (unknown exception)\n";
    }
    return kExitInternal;
}

} // namespace sluice::bake
