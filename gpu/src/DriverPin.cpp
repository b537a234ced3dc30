// keepDriverLoadedForLeakChecks: pin the GL driver in AddressSanitizer builds (Context.h).
#include "sluice/gpu/Context.h"

#include <string_view>

#include <dlfcn.h>
#include <link.h>

#include "sluice/format/support/Sanitizers.h"

namespace sluice::gpu {

void keepDriverLoadedForLeakChecks() {
    if (!kAddressSanitizer)
        return;
    dl_iterate_phdr(
        [](dl_phdr_info* info, std::size_t, void*) {
            const std::string_view name = info->dlpi_name != nullptr ? info->dlpi_name : "";
            // dlopen of a mapped library with RTLD_NOLOAD | RTLD_NODELETE only adds the flag.
            if (name.find("_dri.so") != std::string_view::npos)
                dlopen(info->dlpi_name, RTLD_NOW | RTLD_NOLOAD | RTLD_NODELETE);
            return 0;
        },
        nullptr);
}

} // namespace sluice::gpu
