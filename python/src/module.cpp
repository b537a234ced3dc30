// The _sluice extension module: the C++ half of the `sluice` package (python/sluice/).
#include <nanobind/nanobind.h>

#include "Errors.h"

namespace sluice::py {
void bindBake(nb::module_& m);
void bindSimulation(nb::module_& m);
} // namespace sluice::py

NB_MODULE(_sluice, m) {
    m.doc() = "Sluice's C++ libraries (sluice_bake, sluice_format, sluice_runtime); use the "
              "`sluice` package, which wraps this module.";
    sluice::py::registerErrors(m);
    sluice::py::bindBake(m);
    sluice::py::bindSimulation(m);
    m.attr("__version__") = SLUICE_VERSION;
}
