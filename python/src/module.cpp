// The _sluice extension module: the C++ half of the `sluice` package (python/sluice/).
#include <nanobind/nanobind.h>

#include "Errors.h"
#include "sluice/bake/import/Isolated.h"
#include "sluice/gpu/Context.h"

namespace sluice::py {
void bindBake(nb::module_& m);
void bindSimulation(nb::module_& m);
void bindSurface(nb::module_& m);
} // namespace sluice::py

NB_MODULE(_sluice, m) {
    m.doc() = "Sluice's C++ libraries (sluice_bake, sluice_format, sluice_runtime); use the "
              "`sluice` package, which wraps this module.";
    // A process pool forks this interpreter; its children must not inherit a log4cplus
    // thread pool without its threads (their first mesh import would wait for it forever).
    sluice::bake::prepareForFork();
    sluice::py::registerErrors(m);
    sluice::py::bindBake(m);
    sluice::py::bindSimulation(m);
    sluice::py::bindSurface(m);
    m.def("forked_from_gl_process", &sluice::gpu::forkedFromGlProcess,
          "True in a process forked while its parent had an OpenGL context open: no context "
          "can open here (GPU work needs a fresh process).");
    m.attr("__version__") = SLUICE_VERSION;
}
