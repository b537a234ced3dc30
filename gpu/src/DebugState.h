// Private: what the debug callback writes into, and the checks library calls make afterwards.
#pragma once

#include <algorithm>
#include <cstddef>
#include <mutex>
#include <string_view>
#include <vector>

#include "sluice/gpu/Debug.h"

namespace sluice::gpu {

/// Owned by a Context (on the heap: the callback holds its address).
struct DebugState {
    static constexpr std::size_t kMaxMessages = 256; ///< later ones are counted, not kept

    DebugPolicy policy = DebugPolicy::Assert;
    std::mutex mutex;
    std::vector<DebugMessage> messages;
    std::size_t dropped = 0;
    int muted = 0; ///< > 0 while the library expects errors it returns as values
};

/// Installs the callback for the current context (needs a debug context for full output).
void installDebugCallback(DebugState& state);

/// Debug state of the context current on this thread, or null (no debug context).
DebugState* currentDebugState();
void setCurrentDebugState(DebugState* state);

/// Drains the recorded errors; keeps the other messages for takeDebugMessages().
std::vector<DebugMessage> takeDebugErrors(DebugState& state);

/// Under DebugPolicy::Assert: a SLUICE_ASSERT failure naming `where` if errors were recorded.
/// Library calls end with it so a broken GL call fails next to its cause.
void failOnDebugErrors(const char* where);

/// Mutes the debug callback of the current context while the library provokes errors that it
/// reports as values (compile failures, out-of-memory allocations).
class DebugMute {
public:
    DebugMute();
    ~DebugMute();
    DebugMute(const DebugMute&) = delete;
    DebugMute& operator=(const DebugMute&) = delete;

private:
    DebugState* m_state;
};

/// Length to pass to glObjectLabel: longer labels are an error, GL_MAX_LABEL_LENGTH is >= 256.
inline GLsizei labelLength(std::string_view label) {
    return static_cast<GLsizei>(std::min<std::size_t>(label.size(), 255));
}

/// Drops pending glGetError flags (bounded), so the next glGetError() reflects the next call.
void clearGlErrors();

} // namespace sluice::gpu
