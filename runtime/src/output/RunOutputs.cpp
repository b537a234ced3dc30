// Output paths: every check before the first folder is created, then the folders.
#include "output/RunOutputs.h"

#include <filesystem>
#include <system_error>

#include <unistd.h>

namespace sluice::rt {
namespace {

namespace fs = std::filesystem;

/// The folder a run must create or write into for `output`: the parent of a file (the working
/// folder when there is none), the folder itself otherwise.
fs::path folderOf(const RunOutput& output) {
    const fs::path path(output.path);
    if (output.folder)
        return path;
    return path.has_parent_path() ? path.parent_path() : fs::path(".");
}

Result<void> checkTarget(const RunOutput& output) {
    std::error_code ec;
    const fs::file_status status = fs::status(output.path, ec);
    if (!output.folder && fs::is_directory(status))
        return fail(ErrorCode::InvalidArgument,
                    output.option + " " + output.path + ": is a folder; give a file name");
    if (output.folder && fs::exists(status) && !fs::is_directory(status))
        return fail(ErrorCode::InvalidArgument,
                    output.option + " " + output.path + ": is a file; give a folder");
    return {};
}

/// The nearest folder of `folder` and its parents that exists must be a writable folder.
Result<void> checkFolderPath(const RunOutput& output) {
    std::error_code ec;
    for (fs::path at = folderOf(output);; at = at.parent_path()) {
        if (at.empty())
            at = ".";
        const fs::file_status status = fs::status(at, ec);
        if (fs::exists(status)) {
            if (!fs::is_directory(status))
                return fail(ErrorCode::InvalidArgument, output.option + " " + output.path + ": " +
                                                            at.string() +
                                                            " is a file, not a folder");
            if (::access(at.c_str(), W_OK | X_OK) != 0)
                return fail(ErrorCode::Io, output.option + " " + output.path +
                                               ": cannot write "
                                               "into the folder " +
                                               at.string() + " (permission denied)");
            return {};
        }
        if (at == at.parent_path() || at == ".")
            return {};
    }
}

} // namespace

Result<void> prepareRunOutputs(const std::vector<RunOutput>& outputs) {
    for (const RunOutput& output : outputs) {
        if (output.path.empty())
            continue;
        if (auto ok = checkTarget(output); !ok)
            return ok;
        if (auto ok = checkFolderPath(output); !ok)
            return ok;
    }
    for (const RunOutput& output : outputs) {
        if (output.path.empty())
            continue;
        std::error_code ec;
        fs::create_directories(folderOf(output), ec);
        if (ec)
            return fail(ErrorCode::Io, output.option + " " + output.path +
                                           ": cannot create the folder " +
                                           folderOf(output).string() + ": " + ec.message());
    }
    return {};
}

} // namespace sluice::rt
