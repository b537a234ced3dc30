// Bindings of the baker: meshes, colliders (zero-copy views of the grid), bake, validate, VDB.
#include <cstring>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/optional.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/tuple.h>
#include <nanobind/stl/vector.h>

#include "Errors.h"
#include "sluice/bake/interop/VdbIO.h"
#include "sluice/bake/jobs/BakeJob.h"
#include "sluice/bake/jobs/BatchJob.h"
#include "sluice/bake/jobs/ValidateJob.h"
#include "sluice/bake/sparse/SparseBaker.h"
#include "sluice/format/asset/AssetIO.h"
#include "sluice/format/asset/SdfSampler.h"
#include "sluice/format/support/AtomicFile.h"

namespace sluice::py {
namespace {

using Vertices = nb::ndarray<double, nb::numpy, nb::shape<-1, 3>>;
using Triangles = nb::ndarray<std::uint32_t, nb::numpy, nb::shape<-1, 3>>;

/// A mesh ready to bake (bake::ImportedMesh), owned by Python.
struct Mesh {
    bake::ImportedMesh mesh;
    std::string path; ///< the file it was read from; empty for arrays
};

/// A collider asset, owned by Python; `values` views its distances.
struct Collider {
    format::ColliderAsset asset;
    std::string path;      ///< the file it was read from or saved to; empty otherwise
    bool levelSet = false; ///< read from a .vdb grid
};

Mesh loadMesh(const std::string& path, double scale) {
    Result<bake::ImportedMesh> mesh = [&] {
        nb::gil_scoped_release release;
        return bake::loadMeshFile(path, scale);
    }();
    return Mesh{take(std::move(mesh), Family::Mesh, "cannot read mesh", path), path};
}

Mesh meshFromArrays(nb::ndarray<const double, nb::shape<-1, 3>, nb::c_contig> vertices,
                    nb::ndarray<const std::uint32_t, nb::shape<-1, 3>, nb::c_contig> triangles,
                    const std::string& name) {
    std::span<const glm::dvec3> v(reinterpret_cast<const glm::dvec3*>(vertices.data()),
                                  vertices.shape(0));
    std::span<const glm::uvec3> t(reinterpret_cast<const glm::uvec3*>(triangles.data()),
                                  triangles.shape(0));
    return Mesh{take(bake::meshFromArrays(v, t, name), Family::Mesh, "cannot use mesh", name), {}};
}

nb::object jsonLoads(const std::string& text) {
    return nb::module_::import_("json").attr("loads")(text);
}

Collider readAsset(const std::string& path) {
    Result<format::ColliderAsset> asset = [&] {
        nb::gil_scoped_release release;
        return bake::loadAssetFile(path);
    }();
    const bool vdb = path.size() >= 4 && [&] {
        std::string ext = path.substr(path.size() - 4);
        for (char& c : ext)
            c = char(std::tolower(static_cast<unsigned char>(c)));
        return ext == ".vdb";
    }();
    return Collider{take(std::move(asset), Family::Asset, "cannot read asset", path), path, vdb};
}

Collider bakeMesh(const Mesh& mesh, const bake::BakeRequest& request, bool bar,
                  nb::object callback) {
    Result<bake::BakeSettings> settings = bake::bakeSettingsFor(request);
    if (!settings)
        raise(Family::Argument, settings.error());
    const bake::Box bounds = mesh.mesh.soup.bounds();
    const std::string shown = mesh.path.empty() ? mesh.mesh.sourceFile : mesh.path;
    const Result<double> band = bake::requestBand(request, bounds, settings->grid);
    if (!band)
        raise(Family::Argument, band.error());
    Result<bake::GridSpec> grid = request.sparse
                                      ? bake::sparseGridFor(bounds, settings->grid, *band)
                                      : bake::gridFor(bounds, settings->grid);
    if (!grid)
        raise(Family::Bake, grid.error(), "cannot bake", shown);
    bake::Progress progress("baking " + mesh.mesh.sourceFile, grid->pointCount(), bar);
    Result<bake::BakeOutcome> outcome = runReleased(progress, std::move(callback), [&] {
        Result<bake::BakeOutcome> r = bake::bakeMesh(mesh.mesh, request, &progress);
        progress.finish();
        return r;
    });
    if (!outcome) {
        const Error& e = outcome.error();
        // The command line's words; error_class() makes GPU codes a GpuError.
        const bool noContext = e.code == ErrorCode::NoGlContext;
        raise(Family::Bake, e,
              noContext ? "no GPU context for --backend gpu (use --backend cgal)" : "cannot bake",
              noContext ? std::string() : shown);
    }
    if (!outcome->fallback.empty())
        nb::module_::import_("warnings")
            .attr("warn")("no OpenGL 4.5 context (" + outcome->fallback +
                          "); baked on the CPU with the CGAL backend");
    Collider collider{std::move(outcome->asset), {}, false};
    take(bake::encodeBaked(collider.asset), Family::Bake, "cannot encode the asset for", shown);
    return collider;
}

nb::ndarray<nb::numpy, float, nb::ndim<3>> values(nb::handle self) {
    Collider& c = nb::cast<Collider&>(self);
    // A sparse asset keeps its samples in a NanoVDB tree: there is no dense array to view.
    if (c.asset.sparse())
        raise(Family::Asset,
              Error{ErrorCode::Unsupported,
                    "a sparse (NanoVDB) collider has no dense values; use sample(), or bake "
                    "without --sparse"},
              {}, c.path);
    const glm::uvec3 d = c.asset.meta.dims;
    const std::size_t shape[3] = {d.x, d.y, d.z};
    const std::int64_t strides[3] = {1, std::int64_t(d.x), std::int64_t(d.x) * d.y};
    // The array keeps the Collider alive (owner = self): no copy, memory shared.
    return nb::ndarray<nb::numpy, float, nb::ndim<3>>(c.asset.distances.data(), 3, shape, self,
                                                      strides);
}

nb::tuple
sample(const Collider& c,
       nb::ndarray<const double, nb::shape<-1, 3>, nb::c_contig, nb::device::cpu> points) {
    const std::size_t n = points.shape(0);
    auto* phi = new float[n];
    auto* grad = new double[n * 3];
    {
        nb::gil_scoped_release release;
        const format::SdfSampler sampler(c.asset);
        const double* p = points.data();
        for (std::size_t i = 0; i < n; ++i) {
            const glm::dvec3 x(p[3 * i], p[3 * i + 1], p[3 * i + 2]);
            phi[i] = sampler.value(x);
            const glm::dvec3 g = sampler.gradient(x);
            grad[3 * i] = g.x, grad[3 * i + 1] = g.y, grad[3 * i + 2] = g.z;
        }
    }
    nb::capsule ownPhi(phi, [](void* q) noexcept { delete[] static_cast<float*>(q); });
    nb::capsule ownGrad(grad, [](void* q) noexcept { delete[] static_cast<double*>(q); });
    return nb::make_tuple(nb::ndarray<nb::numpy, float, nb::ndim<1>>(phi, {n}, ownPhi),
                          nb::ndarray<nb::numpy, double, nb::ndim<2>>(grad, {n, 3}, ownGrad));
}

void save(Collider& c, const std::string& path) {
    Result<void> ok;
    {
        nb::gil_scoped_release release;
        Result<std::vector<std::byte>> bytes = bake::encodeBaked(c.asset);
        ok = bytes ? format::writeFileAtomic(path, *bytes) : Result<void>(bytes.error());
    }
    if (!ok)
        raise(ok.error().code == ErrorCode::Io ? Family::File : Family::Asset, ok.error(),
              "cannot write", path);
    c.path = path;
}

std::string validate(const Collider& c, const Mesh& mesh, const bake::ValidateRequest& request,
                     bool bar, nb::object callback) {
    bake::ValidateRequest req = request;
    req.levelSetSource = c.levelSet;
    const std::uint64_t points = bake::validatePointCount(c.asset, req);
    bake::Progress progress("validating", points, bar);
    Result<bake::ValidateOutcome> outcome = runReleased(progress, std::move(callback), [&] {
        Result<bake::ValidateOutcome> r = bake::validateAsset(c.asset, mesh.mesh, req, &progress);
        progress.finish();
        return r;
    });
    if (!outcome)
        raise(outcome.error().code == ErrorCode::InvalidArgument ? Family::Argument : Family::Bake,
              outcome.error(),
              "cannot validate '" + (c.path.empty() ? c.asset.meta.sourceFile : c.path) +
                  "' against '" + (mesh.path.empty() ? mesh.mesh.sourceFile : mesh.path) + "'");
    return bake::validateReportJson(*outcome, c.asset, mesh.mesh, c.path, mesh.path, req, false);
}

nb::dict entryDict(const bake::BatchEntry& e) {
    nb::dict d;
    d["mesh"] = e.mesh;
    d["output"] = e.output;
    d["label"] = e.label;
    d["resolution"] = e.request.resolution;
    d["voxelSize"] = e.request.voxelSize;
    d["padding"] = e.request.padding;
    d["sign"] = e.request.sign;
    d["storage"] = e.request.storage;
    d["scale"] = e.request.scale;
    d["backend"] = e.request.backend;
    d["sparse"] = e.request.sparse;
    d["band"] = e.request.band;
    d["forSpacing"] = e.request.forSpacing;
    d["forKernelRadius"] = e.request.forKernelRadius;
    return d;
}

nb::list readManifest(const std::string& path) {
    std::vector<bake::BatchEntry> entries = take(bake::readBatchEntries(path), Family::Argument);
    nb::list out;
    for (const bake::BatchEntry& e : entries)
        out.append(entryDict(e));
    return out;
}

nb::dict bakeEntry(const std::string& mesh, const std::string& output, const std::string& label,
                   const bake::BakeRequest& request, bool force, bool bar, nb::object callback) {
    const bake::BatchEntry entry{mesh, output, label, request};
    bake::Progress progress("baking " + label, 0, bar);
    Result<bake::BatchEntryResult> result = runReleased(progress, std::move(callback), [&] {
        Result<bake::BatchEntryResult> r = bake::bakeBatchEntry(entry, force, &progress);
        progress.finish();
        return r;
    });
    if (!result)
        raise(result.error().code == ErrorCode::InvalidArgument ? Family::Argument : Family::Bake,
              result.error());
    nb::dict d;
    d["output"] = output;
    d["label"] = label;
    d["status"] = result->fresh ? "fresh" : "baked";
    d["seconds"] = result->seconds;
    d["points"] = result->points;
    d["maxError"] = result->maxError ? nb::cast(*result->maxError) : nb::none();
    return d;
}

// The requests' option classes.
void bindRequests(nb::module_& m) {
    nb::class_<bake::BakeRequest>(m, "BakeRequest",
                                  "The options of one bake (as `sluice-bake bake`).")
        .def(nb::init<>())
        .def_rw("backend", &bake::BakeRequest::backend)
        .def_rw("resolution", &bake::BakeRequest::resolution)
        .def_rw("voxel_size", &bake::BakeRequest::voxelSize)
        .def_rw("padding", &bake::BakeRequest::padding)
        .def_rw("sign", &bake::BakeRequest::sign)
        .def_rw("storage", &bake::BakeRequest::storage)
        .def_rw("scale", &bake::BakeRequest::scale)
        .def_rw("sparse", &bake::BakeRequest::sparse)
        .def_rw("band", &bake::BakeRequest::band)
        .def_rw("for_spacing", &bake::BakeRequest::forSpacing)
        .def_rw("for_kernel_radius", &bake::BakeRequest::forKernelRadius)
        .def_rw("volume_maps", &bake::BakeRequest::volumeMaps);

    nb::class_<bake::ValidateRequest>(m, "ValidateRequest",
                                      "The options of one validation (as `sluice-bake validate`).")
        .def(nb::init<>())
        .def_rw("sign", &bake::ValidateRequest::sign)
        .def_rw("samples", &bake::ValidateRequest::samples)
        .def_rw("seed", &bake::ValidateRequest::seed)
        .def_rw("max_error", &bake::ValidateRequest::maxError, nb::arg().none())
        .def_rw("max_sign_errors_percent", &bake::ValidateRequest::maxSignErrorsPercent);
}

// Mesh, load_mesh and mesh_from_arrays.
void bindMesh(nb::module_& m) {
    nb::class_<Mesh>(m, "Mesh", "A triangle mesh ready to bake: welded vertices and triangles.")
        .def_prop_ro(
            "vertices",
            [](nb::handle self) {
                Mesh& mesh = nb::cast<Mesh&>(self);
                const std::size_t shape[2] = {mesh.mesh.soup.positions.size(), 3};
                return nb::ndarray<nb::numpy, const double, nb::shape<-1, 3>>(
                    mesh.mesh.soup.positions.data(), 2, shape, self);
            },
            nb::rv_policy::reference_internal, "(N, 3) float64 [world units], a read-only view")
        .def_prop_ro(
            "triangles",
            [](nb::handle self) {
                Mesh& mesh = nb::cast<Mesh&>(self);
                const std::size_t shape[2] = {mesh.mesh.soup.triangles.size(), 3};
                return nb::ndarray<nb::numpy, const std::uint32_t, nb::shape<-1, 3>>(
                    mesh.mesh.soup.triangles.data(), 2, shape, self);
            },
            nb::rv_policy::reference_internal, "(M, 3) uint32 vertex indices, a read-only view")
        .def_prop_ro(
            "diagnostics",
            [](const Mesh& mesh) {
                return jsonLoads(bake::meshDiagnosticsJson(mesh.mesh.diagnostics));
            },
            "What the baker reports about the mesh (counts, closed, self-intersecting).")
        .def_prop_ro("source_file", [](const Mesh& mesh) { return mesh.mesh.sourceFile; })
        .def_prop_ro("source_hash", [](const Mesh& mesh) { return mesh.mesh.sourceHash; })
        .def_prop_ro("path", [](const Mesh& mesh) { return mesh.path; });

    m.def("load_mesh", &loadMesh, nb::arg("path"), nb::arg("scale") = 1.0,
          "Reads a mesh file (assimp) or a level-set .vdb at `scale`, as sluice-bake does.");
    m.def("mesh_from_arrays", &meshFromArrays, nb::arg("vertices"), nb::arg("triangles"),
          nb::arg("name") = "arrays",
          "A Mesh from (N, 3) float64 vertices and (M, 3) uint32 "
          "triangles (copied).");
}

// Collider: the grid as a NumPy view, its metadata, save, export and the sampler.
void bindCollider(nb::module_& m) {
    nb::class_<Collider>(m, "Collider", "A baked collider: a dense signed distance grid.")
        .def_prop_ro("values", &values, nb::rv_policy::reference_internal,
                     "phi[i, j, k] [world units], negative inside: a writable float32 view of "
                     "the grid (no copy), shape dims, x fastest in memory.")
        .def_prop_ro("origin",
                     [](const Collider& c) {
                         const glm::dvec3 o = c.asset.meta.origin;
                         return std::make_tuple(o.x, o.y, o.z);
                     })
        .def_prop_ro("voxel_size", [](const Collider& c) { return c.asset.meta.voxelSize; })
        .def_prop_ro("dims",
                     [](const Collider& c) {
                         const glm::uvec3 d = c.asset.meta.dims;
                         return std::make_tuple(d.x, d.y, d.z);
                     })
        .def_prop_ro("metadata_json",
                     [](const Collider& c) { return bake::colliderMetaJson(c.asset.meta); })
        .def_prop_ro("path", [](const Collider& c) { return c.path; })
        .def_prop_ro("volume_map_supports",
                     [](const Collider& c) {
                         std::vector<double> supports;
                         for (const format::VolumeMap& map : c.asset.volumeMaps)
                             supports.push_back(map.support);
                         return supports;
                     })
        .def("save", &save, nb::arg("path"),
             "Writes the asset atomically (as the command line): replaced whole or untouched.")
        .def(
            "export_vdb",
            [](const Collider& c, const std::string& path) {
                Result<void> ok;
                {
                    nb::gil_scoped_release release;
                    ok = bake::exportVdb(c.asset, path);
                }
                if (!ok)
                    raise(Family::File, ok.error(), "cannot export", path);
            },
            nb::arg("path"), "Writes an OpenVDB float level set (as `sluice-bake export`).")
        .def("sample", &sample, nb::arg("points"),
             "The CPU trilinear sampler at (N, 3) float64 points: (phi (N,) float32, gradient "
             "(N, 3) float64).");
}

} // namespace

void bindBake(nb::module_& m) {
    bindRequests(m);
    bindMesh(m);
    bindCollider(m);

    m.def("read_asset", &readAsset, nb::arg("path"),
          "Reads a collider asset (.slc) or the first float grid of a .vdb.");
    m.def("bake_mesh", &bakeMesh, nb::arg("mesh"), nb::arg("request"), nb::arg("bar"),
          nb::arg("callback").none(), "Bakes a Mesh (the GIL is released).");
    m.def("validate_json", &validate, nb::arg("collider"), nb::arg("mesh"), nb::arg("request"),
          nb::arg("bar"), nb::arg("callback").none(),
          "Validates a collider against a mesh; `sluice-bake validate --json`'s report.");
    m.def("tool_version", &bake::bakeToolVersion);
    m.def("read_batch_manifest", &readManifest, nb::arg("path"),
          "The entries of a batch manifest (as `sluice-bake batch` reads it), paths resolved.");
    m.def("bake_batch_entry", &bakeEntry, nb::arg("mesh"), nb::arg("output"), nb::arg("label"),
          nb::arg("request"), nb::arg("force"), nb::arg("bar"), nb::arg("callback").none(),
          "Bakes one manifest entry unless its output is fresh (as `sluice-bake batch`).");
}

} // namespace sluice::py
