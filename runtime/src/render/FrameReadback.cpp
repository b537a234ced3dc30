// Pixel-pack buffer ring with fences for stall-free frame capture.
#include "sluice/rt/render/FrameReadback.h"

#include "GlObjects.h"
#include "sluice/format/support/Assert.h"

namespace sluice::rt {

struct FrameReadback::Slot {
    BufferHandle buffer;
    std::size_t capacity = 0; // [bytes]
    glm::uvec2 size{0};
    std::uint64_t tag = 0;
    Fence fence;
};

FrameReadback::FrameReadback(std::size_t slots) : m_slots(slots) {
    SLUICE_ASSERT(slots >= 1, "FrameReadback needs at least one slot");
}

FrameReadback::FrameReadback(FrameReadback&&) noexcept = default;
FrameReadback& FrameReadback::operator=(FrameReadback&&) noexcept = default;
FrameReadback::~FrameReadback() = default;

void FrameReadback::request(GLuint framebuffer, glm::uvec2 size, std::uint64_t tag) {
    if (m_inFlight == m_slots.size())
        finishOldest(true);
    Slot& slot = m_slots[m_next];
    const std::size_t bytes = std::size_t(size.x) * size.y * 3;
    if (slot.capacity < bytes) {
        GLuint id = 0;
        glCreateBuffers(1, &id);
        slot.buffer = BufferHandle(id);
        glNamedBufferStorage(id, GLsizeiptr(bytes), nullptr, 0);
        slot.capacity = bytes;
    }
    slot.size = size;
    slot.tag = tag;
    glBindBuffer(GL_PIXEL_PACK_BUFFER, slot.buffer.id());
    glBindFramebuffer(GL_READ_FRAMEBUFFER, framebuffer);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, GLsizei(size.x), GLsizei(size.y), GL_RGB, GL_UNSIGNED_BYTE, nullptr);
    glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
    slot.fence = Fence::insert();
    m_next = (m_next + 1) % m_slots.size();
    ++m_inFlight;
}

void FrameReadback::finishOldest(bool wait) {
    SLUICE_ASSERT(m_inFlight > 0, "FrameReadback: nothing in flight");
    Slot& slot = m_slots[(m_next + m_slots.size() - m_inFlight) % m_slots.size()];
    if (!slot.fence.signalled(wait) && !wait)
        return;
    ReadbackFrame frame;
    frame.tag = slot.tag;
    frame.image = Image::blank(slot.size.x, slot.size.y);
    glGetNamedBufferSubData(slot.buffer.id(), 0, GLsizeiptr(frame.image.rgb.size()),
                            frame.image.rgb.data());
    flipRows(frame.image.rgb.data(), std::size_t(slot.size.x) * 3, slot.size.y);
    slot.fence.reset();
    m_ready.push_back(std::move(frame));
    --m_inFlight;
}

std::vector<ReadbackFrame> FrameReadback::collect(bool wait) {
    while (m_inFlight > 0) {
        const std::size_t before = m_inFlight;
        finishOldest(wait);
        if (m_inFlight == before)
            break; // the oldest is still running; later ones are too
    }
    std::vector<ReadbackFrame> frames(std::make_move_iterator(m_ready.begin()),
                                      std::make_move_iterator(m_ready.end()));
    m_ready.clear();
    return frames;
}

std::size_t FrameReadback::pending() const {
    return m_inFlight + m_ready.size();
}

} // namespace sluice::rt
