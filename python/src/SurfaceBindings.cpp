// Bindings of the surface reconstruction: (N, 3) points in, a mesh out, in a headless GL
// context of its own.
#include <cstring>
#include <memory>
#include <optional>
#include <vector>

#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/optional.h>

#include "Errors.h"
#include "sluice/gpu/Context.h"
#include "sluice/rt/surface/SurfaceMesh.h"

namespace sluice::py {
namespace {

using Points = nb::ndarray<const float, nb::shape<-1, 3>, nb::c_contig, nb::device::cpu>;

template <class T, class V> nb::ndarray<nb::numpy, T, nb::ndim<2>> rows(const std::vector<V>& v) {
    const std::size_t n = v.size();
    auto* data = new T[n * 3];
    static_assert(sizeof(V) == 3 * sizeof(T));
    if (n > 0)
        std::memcpy(data, v.data(), n * sizeof(V));
    nb::capsule owner(data, [](void* p) noexcept { delete[] static_cast<T*>(p); });
    return nb::ndarray<nb::numpy, T, nb::ndim<2>>(data, {n, 3}, owner);
}

/// A headless context and the compiled surface passes, kept between calls: the Python layer
/// holds one per thread and process (python/sluice/_surface.py), so a call pays neither a
/// context nor a compile.
struct PyMesher {
    std::optional<gpu::Context> context;
    std::unique_ptr<rt::SurfaceReconstructor> reconstructor;

    PyMesher(const PyMesher&) = delete;
    PyMesher& operator=(const PyMesher&) = delete;
    ~PyMesher() {
        // The passes' GL objects are deleted in their own context, or left (see ~PySimulation).
        if (reconstructor && !(context && context->tryMakeCurrent()))
            (void)reconstructor.release();
        reconstructor.reset();
    }

    PyMesher() {
        Result<void> made = [&]() -> Result<void> {
            nb::gil_scoped_release release;
            auto created = gpu::Context::createHeadless();
            if (!created)
                return created.error();
            context.emplace(std::move(*created));
            auto passes = rt::SurfaceReconstructor::create();
            if (!passes)
                return passes.error();
            reconstructor = std::make_unique<rt::SurfaceReconstructor>(std::move(*passes));
            return {};
        }();
        if (!made)
            raise(Family::Simulation, made.error());
    }

    nb::tuple reconstruct(Points points, float particleRadius, float cellSize,
                          float smoothingRadius, float iso, bool anisotropic,
                          std::optional<float> centreSmoothing, bool poly6,
                          std::optional<bool> normalised) {
        rt::SurfaceOptions options;
        options.particleRadius = particleRadius;
        options.cellSize = cellSize;
        options.smoothingRadius = smoothingRadius;
        options.iso = iso;
        options.anisotropic = anisotropic;
        options.centreSmoothing = centreSmoothing;
        options.kernel = poly6 ? rt::SurfaceFieldKernel::Poly6 : rt::SurfaceFieldKernel::Gaussian;
        options.densityNormalised = normalised;
        std::vector<glm::vec3> copy(points.shape(0));
        if (!copy.empty())
            std::memcpy(copy.data(), points.data(), copy.size() * sizeof(glm::vec3));
        Result<rt::SurfaceMesh> mesh = [&]() -> Result<rt::SurfaceMesh> {
            nb::gil_scoped_release release;
            context->makeCurrent();
            return reconstructor->reconstruct(copy, options);
        }();
        if (!mesh)
            raise(mesh.error().code == ErrorCode::InvalidArgument ? Family::Argument
                                                                  : Family::Simulation,
                  mesh.error());
        nb::dict timings;
        for (const auto& [name, member] : rt::kSurfaceStages)
            timings[name] = mesh->timings.*member;
        return nb::make_tuple(rows<float>(mesh->vertices), rows<float>(mesh->normals),
                              rows<std::uint32_t>(mesh->triangles), timings);
    }
};

} // namespace

void bindSurface(nb::module_& m) {
    nb::class_<PyMesher>(m, "SurfaceMesher",
                         "A headless GL context with the surface passes compiled.")
        .def(nb::init<>())
        .def("reconstruct", &PyMesher::reconstruct, nb::arg("points"), nb::arg("particle_radius"),
             nb::arg("cell_size"), nb::arg("smoothing_radius"), nb::arg("iso"),
             nb::arg("anisotropic"), nb::arg("centre_smoothing").none(), nb::arg("poly6"),
             nb::arg("normalised").none(),
             "The fluid surface of (N, 3) float32 points on the GPU: (vertices (V, 3) float32, "
             "normals (V, 3) float32, triangles (T, 3) uint32, stage times {name: ms}); zeros "
             "and None take the defaults.");
}

} // namespace sluice::py
