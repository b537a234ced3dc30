// NanoVDB's tool headers (file IO and the OpenVDB conversions) in one place, after OpenVDB's,
// with their warnings silenced so -Werror never trips on them.
#pragma once

#include "interop/VdbHeaders.h"

SLUICE_VDB_WARNINGS_OFF
#ifndef __clang__ // GCC only: clang has no such group and warns about the name
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include <nanovdb/util/IO.h>
#include <nanovdb/util/NanoToOpenVDB.h>
#include <nanovdb/util/OpenToNanoVDB.h>
SLUICE_VDB_WARNINGS_ON
