// GL debug output: the callback, the per-thread current state and the fail-loudly checks.
#include "DebugState.h"

#include <string>

#include "sluice/format/support/Assert.h"

namespace sluice::gpu {
namespace {

thread_local DebugState* t_current = nullptr;

const char* severityName(GLenum severity) {
    switch (severity) {
    case GL_DEBUG_SEVERITY_HIGH:
        return "high";
    case GL_DEBUG_SEVERITY_MEDIUM:
        return "medium";
    case GL_DEBUG_SEVERITY_LOW:
        return "low";
    case GL_DEBUG_SEVERITY_NOTIFICATION:
        return "notification";
    default:
        return "unknown severity";
    }
}

const char* sourceName(GLenum source) {
    switch (source) {
    case GL_DEBUG_SOURCE_API:
        return "api";
    case GL_DEBUG_SOURCE_WINDOW_SYSTEM:
        return "window system";
    case GL_DEBUG_SOURCE_SHADER_COMPILER:
        return "shader compiler";
    case GL_DEBUG_SOURCE_THIRD_PARTY:
        return "third party";
    case GL_DEBUG_SOURCE_APPLICATION:
        return "application";
    default:
        return "other";
    }
}

const char* typeName(GLenum type) {
    switch (type) {
    case GL_DEBUG_TYPE_ERROR:
        return "GL error";
    case GL_DEBUG_TYPE_DEPRECATED_BEHAVIOR:
        return "GL deprecated";
    case GL_DEBUG_TYPE_UNDEFINED_BEHAVIOR:
        return "GL undefined behaviour";
    case GL_DEBUG_TYPE_PORTABILITY:
        return "GL portability";
    case GL_DEBUG_TYPE_PERFORMANCE:
        return "GL performance";
    default:
        return "GL message";
    }
}

// Never throws or asserts: it runs inside the driver, whose C frames cannot be unwound.
void GLAPIENTRY onDebugMessage(GLenum source, GLenum type, GLuint id, GLenum severity,
                               GLsizei length, const GLchar* text, const void* user) {
    if (severity == GL_DEBUG_SEVERITY_NOTIFICATION)
        return;
    auto* state = static_cast<DebugState*>(const_cast<void*>(user));
    try {
        std::lock_guard lock(state->mutex);
        if (state->muted > 0)
            return;
        if (state->messages.size() >= DebugState::kMaxMessages) {
            ++state->dropped;
            return;
        }
        DebugMessage message{source, type, id, severity, {}};
        message.text =
            length >= 0 ? std::string(text, static_cast<std::size_t>(length)) : std::string(text);
        state->messages.push_back(std::move(message));
    } catch (...) {
        // Out of memory while recording a message: drop it rather than unwind into the driver.
    }
}

} // namespace

bool DebugMessage::isError() const {
    return type == GL_DEBUG_TYPE_ERROR || severity == GL_DEBUG_SEVERITY_HIGH;
}

std::string DebugMessage::describe() const {
    return std::string(typeName(type)) + " (" + severityName(severity) + ", " + sourceName(source) +
           ", id " + std::to_string(id) + "): " + text;
}

void installDebugCallback(DebugState& state) {
    glEnable(GL_DEBUG_OUTPUT);
    // Synchronous delivery: the message arrives inside the offending call, on this thread.
    glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
    glDebugMessageCallback(&onDebugMessage, &state);
    glDebugMessageControl(GL_DONT_CARE, GL_DONT_CARE, GL_DEBUG_SEVERITY_NOTIFICATION, 0, nullptr,
                          GL_FALSE);
}

DebugState* currentDebugState() {
    return t_current;
}
void setCurrentDebugState(DebugState* state) {
    t_current = state;
}

std::vector<DebugMessage> takeDebugErrors(DebugState& state) {
    std::lock_guard lock(state.mutex);
    std::vector<DebugMessage> errors;
    std::vector<DebugMessage> rest;
    for (auto& message : state.messages)
        (message.isError() ? errors : rest).push_back(std::move(message));
    state.messages = std::move(rest);
    return errors;
}

void failOnDebugErrors(const char* where) {
    DebugState* state = t_current;
    if (state == nullptr || state->policy != DebugPolicy::Assert)
        return;
    std::vector<DebugMessage> errors = takeDebugErrors(*state);
    if (errors.empty())
        return;
    std::string text = std::string("GL debug output reported errors in ") + where + ":";
    for (const auto& error : errors)
        text += "\n  " + error.describe();
    SLUICE_ASSERT(errors.empty(), text.c_str());
}

DebugMute::DebugMute() : m_state(t_current) {
    if (m_state != nullptr) {
        std::lock_guard lock(m_state->mutex);
        ++m_state->muted;
    }
}

DebugMute::~DebugMute() {
    if (m_state != nullptr) {
        std::lock_guard lock(m_state->mutex);
        --m_state->muted;
    }
}

void clearGlErrors() {
    // A lost context can return an error forever; 32 distinct flags is more than GL has.
    for (int i = 0; i < 32 && glGetError() != GL_NO_ERROR; ++i) {
    }
}

} // namespace sluice::gpu
