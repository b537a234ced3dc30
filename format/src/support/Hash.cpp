// XXH3-64 over memory and over files, through libxxhash.
#include "sluice/format/support/Hash.h"

#include <array>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>

#include <xxhash.h>

namespace sluice::format {

std::uint64_t xxh3(std::span<const std::byte> bytes) {
    return XXH3_64bits(bytes.data(), bytes.size());
}

std::string hex64(std::uint64_t value) {
    static constexpr char kDigits[] = "0123456789abcdef";
    std::string out(16, '0');
    for (int i = 15; i >= 0; --i) {
        out[std::size_t(i)] = kDigits[value & 0xFu];
        value >>= 4;
    }
    return out;
}

Result<std::string> hashFileHex(const std::filesystem::path& path) {
    struct FileCloser {
        void operator()(std::FILE* f) const { std::fclose(f); }
    };
    struct StateFree {
        void operator()(XXH3_state_t* s) const { XXH3_freeState(s); }
    };
    std::unique_ptr<std::FILE, FileCloser> file(std::fopen(path.c_str(), "rb"));
    if (!file)
        return fail(ErrorCode::Io,
                    path.string() + ": cannot open for hashing: " + std::strerror(errno));
    std::unique_ptr<XXH3_state_t, StateFree> state(XXH3_createState());
    if (!state || XXH3_64bits_reset(state.get()) == XXH_ERROR)
        return fail(ErrorCode::Io, path.string() + ": cannot allocate the hash state");

    std::array<unsigned char, 1u << 16> chunk;
    for (;;) {
        const std::size_t got = std::fread(chunk.data(), 1, chunk.size(), file.get());
        if (got > 0)
            XXH3_64bits_update(state.get(), chunk.data(), got);
        if (got < chunk.size()) {
            if (std::ferror(file.get()))
                return fail(ErrorCode::Io,
                            path.string() + ": read error while hashing: " + std::strerror(errno));
            break;
        }
    }
    return hex64(XXH3_64bits_digest(state.get()));
}

} // namespace sluice::format
