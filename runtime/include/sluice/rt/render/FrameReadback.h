// Reads rendered frames back to the CPU without stalling: each request copies the pixels into a
// pixel-pack buffer on the GPU, and the frame is collected a few frames later, once its fence
// has passed.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "sluice/gpu/Gl.h"
#include "sluice/rt/render/Image.h"

namespace sluice::rt {

/// A frame read back, with the tag it was requested with (a step or frame number).
struct ReadbackFrame {
    std::uint64_t tag = 0;
    Image image;
};

/// A ring of pixel-pack buffers, each with a fence. Needs its context current, destruction
/// included. Move-only.
class FrameReadback {
public:
    /// `slots` copies may be in flight at once (>= 1; 3 covers the usual latency).
    explicit FrameReadback(std::size_t slots = 3);
    FrameReadback(FrameReadback&&) noexcept;
    FrameReadback& operator=(FrameReadback&&) noexcept;
    FrameReadback(const FrameReadback&) = delete;
    FrameReadback& operator=(const FrameReadback&) = delete;
    ~FrameReadback();

    /// Queues a copy of colour attachment 0 of `framebuffer`, `size` pixels, as RGB8. When every
    /// slot is in flight, first waits for the oldest copy (the only case that waits); that frame
    /// is then returned by the next collect().
    void request(GLuint framebuffer, glm::uvec2 size, std::uint64_t tag);

    /// The frames whose copies have finished, oldest first; with `wait`, every frame in flight.
    std::vector<ReadbackFrame> collect(bool wait);

    /// Copies requested and not yet collected.
    std::size_t pending() const;

private:
    struct Slot;
    void finishOldest(bool wait);

    std::vector<Slot> m_slots;
    std::size_t m_next = 0;     // slot of the next request
    std::size_t m_inFlight = 0; // the oldest is m_next - m_inFlight (mod size)
    std::deque<ReadbackFrame> m_ready;
};

} // namespace sluice::rt
