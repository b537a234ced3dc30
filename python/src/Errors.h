// Turning sluice::Error values into the Python exceptions of sluice._errors, and Ctrl-C checks.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>
#include <thread>

#include <nanobind/nanobind.h>

#include "sluice/bake/jobs/Progress.h"
#include "sluice/format/support/Result.h"

namespace sluice::py {

namespace nb = nanobind;

/// Where an error came from; picks the Python class together with the code (docs/python.md).
enum class Family { File, Mesh, Asset, Scene, Bake, Simulation, Argument };

/// Thrown by the bindings and translated into sluice._errors.<class>(message, code).
struct SluiceError : std::runtime_error {
    SluiceError(Family familyOf, ErrorCode codeOf, const std::string& message)
        : std::runtime_error(message), family(familyOf), code(codeOf) {}
    Family family;
    ErrorCode code;
};

/// Throws SluiceError with `error.message()` ("<detail> [<Code>]"), prefixed by `what` as the
/// command lines print it: "<what> '<path>': ..." unless the detail already names `path`.
[[noreturn]] void raise(Family family, const Error& error, const std::string& what = {},
                        const std::string& path = {});

/// Unwraps a Result or raises.
template <class T>
T take(Result<T>&& result, Family family, const std::string& what = {},
       const std::string& path = {}) {
    if (!result)
        raise(family, result.error(), what, path);
    return std::move(result.value());
}

/// Registers the exception translator (sluice._errors is imported lazily, at the first error).
void registerErrors(nb::module_& m);

/// A Progress poll for work run with the GIL released on the calling thread: on that thread,
/// at most 20 times a second, it takes the GIL, checks for Ctrl-C (PyErr_CheckSignals) and calls
/// `callback(done, total)` if it is not None. A pending signal or an exception from the callback
/// cancels the work (Progress throws ProgressCancelled); the Python error stays set.
class PollState {
public:
    explicit PollState(nb::object callback);
    bake::Progress::Poll poll();
    /// Call with the GIL held after catching ProgressCancelled: raises the pending Python error.
    [[noreturn]] void raiseInterrupted();

private:
    nb::object m_callback;
    std::thread::id m_thread;
    std::chrono::steady_clock::time_point m_last;
};

/// Runs `work` with the GIL released and a poll installed on `progress`; a Ctrl-C or a failing
/// callback raises the Python error once the work has stopped.
template <class F> auto runReleased(bake::Progress& progress, nb::object callback, F&& work) {
    PollState state(std::move(callback));
    progress.setPoll(state.poll());
    try {
        nb::gil_scoped_release release;
        return work();
    } catch (const bake::ProgressCancelled&) {
        state.raiseInterrupted();
    }
}

} // namespace sluice::py
