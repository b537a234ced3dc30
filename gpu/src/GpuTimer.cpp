// Ring of GL_TIMESTAMP query pairs: non-blocking collection, blocking only when it is full.
#include "sluice/gpu/GpuTimer.h"

#include <utility>

#include "DebugState.h"
#include "sluice/format/support/Assert.h"

namespace sluice::gpu {

GpuTimer::GpuTimer(std::size_t ringSize) : m_queries(2 * ringSize, 0) {
    SLUICE_ASSERT(ringSize >= 1, "GpuTimer needs at least one slot");
    glCreateQueries(GL_TIMESTAMP, static_cast<GLsizei>(m_queries.size()), m_queries.data());
    failOnDebugErrors("GpuTimer::GpuTimer");
}

GpuTimer::GpuTimer(GpuTimer&& other) noexcept
    : m_queries(std::move(other.m_queries)), m_next(other.m_next), m_pending(other.m_pending),
      m_active(other.m_active), m_latest(other.m_latest), m_completed(other.m_completed),
      m_totalNs(other.m_totalNs) {
    other.m_queries.clear();
    other.m_pending = 0;
    other.m_active = false;
}

GpuTimer& GpuTimer::operator=(GpuTimer&& other) noexcept {
    if (this != &other) {
        release();
        m_queries = std::move(other.m_queries);
        m_next = other.m_next;
        m_pending = other.m_pending;
        m_active = other.m_active;
        m_latest = other.m_latest;
        m_completed = other.m_completed;
        m_totalNs = other.m_totalNs;
        other.m_queries.clear();
        other.m_pending = 0;
        other.m_active = false;
    }
    return *this;
}

GpuTimer::~GpuTimer() {
    release();
}

void GpuTimer::release() {
    if (!m_queries.empty())
        glDeleteQueries(static_cast<GLsizei>(m_queries.size()), m_queries.data());
    m_queries.clear();
    m_active = false;
    m_pending = 0;
}

void GpuTimer::begin() {
    SLUICE_ASSERT(!m_queries.empty(), "GpuTimer::begin on a moved-from timer");
    SLUICE_ASSERT(!m_active, "GpuTimer::begin twice without end");
    const std::size_t slots = m_queries.size() / 2;
    if (m_pending == slots) {
        poll();
        // Still full: the GPU is more than a ring behind; wait rather than lose a measurement.
        if (m_pending == slots)
            collectOldest(true);
    }
    glQueryCounter(m_queries[2 * m_next], GL_TIMESTAMP);
    m_active = true;
}

void GpuTimer::end() {
    SLUICE_ASSERT(m_active, "GpuTimer::end without begin");
    glQueryCounter(m_queries[2 * m_next + 1], GL_TIMESTAMP);
    m_active = false;
    m_next = (m_next + 1) % (m_queries.size() / 2);
    ++m_pending;
    failOnDebugErrors("GpuTimer::end");
}

bool GpuTimer::collectOldest(bool wait) {
    if (m_pending == 0)
        return false;
    const std::size_t slots = m_queries.size() / 2;
    const std::size_t oldest = (m_next + slots - m_pending) % slots;
    const GLuint start = m_queries[2 * oldest];
    const GLuint end = m_queries[2 * oldest + 1];
    if (!wait) {
        GLint available = GL_FALSE;
        glGetQueryObjectiv(end, GL_QUERY_RESULT_AVAILABLE, &available);
        if (available == GL_TRUE)
            glGetQueryObjectiv(start, GL_QUERY_RESULT_AVAILABLE, &available);
        if (available != GL_TRUE)
            return false;
    }
    GLuint64 startNs = 0;
    GLuint64 endNs = 0;
    glGetQueryObjectui64v(start, GL_QUERY_RESULT, &startNs);
    glGetQueryObjectui64v(end, GL_QUERY_RESULT, &endNs);
    const std::uint64_t ns = endNs > startNs ? endNs - startNs : 0;
    --m_pending;
    m_latest = ns;
    ++m_completed;
    m_totalNs += ns;
    return true;
}

std::optional<std::uint64_t> GpuTimer::poll() {
    bool any = false;
    // Queries finish in order, so stop at the first one still in flight.
    while (collectOldest(false))
        any = true;
    return any ? m_latest : std::nullopt;
}

std::uint64_t GpuTimer::elapsedNs() {
    SLUICE_ASSERT(!m_active, "GpuTimer::elapsedNs between begin and end");
    while (collectOldest(true)) {
    }
    SLUICE_ASSERT(m_latest.has_value(), "GpuTimer::elapsedNs before any measurement");
    return *m_latest;
}

} // namespace sluice::gpu
