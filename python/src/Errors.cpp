// Turning sluice::Error values into the Python exceptions of sluice._errors, and Ctrl-C checks.
#include "Errors.h"

#include <Python.h>
#include <nanobind/stl/string.h>

namespace sluice::py {

namespace {

const char* familyName(Family family) {
    switch (family) {
    case Family::File:
        return "file";
    case Family::Mesh:
        return "mesh";
    case Family::Asset:
        return "asset";
    case Family::Scene:
        return "scene";
    case Family::Bake:
        return "bake";
    case Family::Simulation:
        return "simulation";
    case Family::Argument:
        return "argument";
    }
    return "bake";
}

} // namespace

void raise(Family family, const Error& error, const std::string& what, const std::string& path) {
    std::string message = error.message();
    if (!what.empty()) {
        const bool named = path.empty() || error.detail.find(path) != std::string::npos;
        message = (named ? what : what + " '" + path + "'") + ": " + message;
    }
    throw SluiceError(family, error.code, message);
}

void registerErrors(nb::module_& m) {
    nb::register_exception_translator([](const std::exception_ptr& p, void*) {
        try {
            std::rethrow_exception(p);
        } catch (const SluiceError& e) {
            nb::object errors = nb::module_::import_("sluice._errors");
            nb::object cls = errors.attr("error_class")(std::string(errorCodeName(e.code)),
                                                        familyName(e.family));
            nb::object exc = cls(e.what(), std::string(errorCodeName(e.code)));
            PyErr_SetObject(cls.ptr(), exc.ptr());
        }
    });
    m.def(
        "error_code_name", [](int code) { return std::string(errorCodeName(ErrorCode(code))); },
        "The ErrorCode name of a numeric code (for tests).");
}

PollState::PollState(nb::object callback)
    : m_callback(std::move(callback)), m_thread(std::this_thread::get_id()),
      m_last(std::chrono::steady_clock::now()) {}

bake::Progress::Poll PollState::poll() {
    return [this](std::uint64_t done, std::uint64_t total) {
        if (std::this_thread::get_id() != m_thread)
            return true;
        const auto now = std::chrono::steady_clock::now();
        if (now - m_last < std::chrono::milliseconds(50))
            return true;
        m_last = now;
        nb::gil_scoped_acquire acquire;
        if (PyErr_CheckSignals() != 0)
            return false;
        if (m_callback.is_valid() && !m_callback.is_none()) {
            try {
                m_callback(done, total);
            } catch (nb::python_error& e) {
                e.restore();
                return false;
            }
        }
        return true;
    };
}

void PollState::raiseInterrupted() {
    if (PyErr_Occurred())
        throw nb::python_error();
    PyErr_SetNone(PyExc_KeyboardInterrupt);
    throw nb::python_error();
}

} // namespace sluice::py
