// OpenVDB headers in one place, with their warnings silenced so -Werror never trips on them, and
// the library's one-time initialisation.
#pragma once

#include <mutex>

// The warnings OpenVDB's headers trip, off between these two: for the headers here, NanoVDB's
// (NanoVdbHeaders.h) and the OpenVDB tools a benchmark includes besides.
// clang-format off
#define SLUICE_VDB_WARNINGS_OFF                                                                    \
    _Pragma("GCC diagnostic push")                                                                 \
    _Pragma("GCC diagnostic ignored \"-Wshadow\"")                                                 \
    _Pragma("GCC diagnostic ignored \"-Wpedantic\"")                                               \
    _Pragma("GCC diagnostic ignored \"-Wunused-parameter\"")                                       \
    _Pragma("GCC diagnostic ignored \"-Wnon-virtual-dtor\"")
#define SLUICE_VDB_WARNINGS_ON _Pragma("GCC diagnostic pop")
// clang-format on

SLUICE_VDB_WARNINGS_OFF
#include <openvdb/io/File.h>
#include <openvdb/io/Stream.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/VolumeToMesh.h>
SLUICE_VDB_WARNINGS_ON

namespace sluice::bake {

/// openvdb::initialize, once per process, before the first grid is made or read.
inline void initOpenVdb() {
    static std::once_flag once;
    std::call_once(once, [] { openvdb::initialize(); });
}

} // namespace sluice::bake
