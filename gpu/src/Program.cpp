// GLSL program compilation (version and define injection, info logs), uniforms and dispatch.
#include "sluice/gpu/Program.h"

#include <algorithm>
#include <array>

#include "DebugState.h"
#include "shared/ChunkedDispatch.h"
#include "sluice/format/support/Assert.h"

namespace sluice::gpu {
namespace {

bool isIdentifier(std::string_view name) {
    if (name.empty() || (name[0] >= '0' && name[0] <= '9'))
        return false;
    return std::all_of(name.begin(), name.end(), [](char c) {
        return c == '_' || (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') ||
               (c >= '0' && c <= '9');
    });
}

/// Whether `line` is a preprocessor #version directive ("#version", "  # version").
bool isVersionLine(std::string_view line) {
    std::size_t i = line.find_first_not_of(" \t");
    if (i == std::string_view::npos || line[i] != '#')
        return false;
    i = line.find_first_not_of(" \t", i + 1);
    return i != std::string_view::npos && line.substr(i, 7) == "version";
}

const char* stageName(GLenum stage) {
    switch (stage) {
    case GL_COMPUTE_SHADER:
        return "compute shader";
    case GL_VERTEX_SHADER:
        return "vertex shader";
    case GL_FRAGMENT_SHADER:
        return "fragment shader";
    default:
        return "shader";
    }
}

std::string shaderLog(GLuint shader) {
    GLint length = 0;
    glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
    std::string log(static_cast<std::size_t>(std::max(length, 1)), '\0');
    glGetShaderInfoLog(shader, length, nullptr, log.data());
    log.resize(log.find('\0') == std::string::npos ? log.size() : log.find('\0'));
    return log;
}

std::string programLog(GLuint program) {
    GLint length = 0;
    glGetProgramiv(program, GL_INFO_LOG_LENGTH, &length);
    std::string log(static_cast<std::size_t>(std::max(length, 1)), '\0');
    glGetProgramInfoLog(program, length, nullptr, log.data());
    log.resize(log.find('\0') == std::string::npos ? log.size() : log.find('\0'));
    return log;
}

Result<GLuint> compileStage(GLenum stage, std::string_view name, std::string_view source,
                            std::span<const ShaderDefine> defines) {
    const std::string text = assembleShaderSource(source, defines);
    GLuint shader = glCreateShader(stage);
    const GLchar* pointer = text.c_str();
    const auto length = static_cast<GLint>(text.size());
    glShaderSource(shader, 1, &pointer, &length);
    glCompileShader(shader);
    GLint status = GL_FALSE;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &status);
    if (status != GL_TRUE) {
        std::string log = shaderLog(shader);
        glDeleteShader(shader);
        return fail(ErrorCode::ShaderCompile,
                    std::string(name) + " (" + stageName(stage) + ") does not compile:\n" + log);
    }
    return shader;
}

} // namespace

std::uint32_t groupCount(std::uint64_t items, std::uint32_t localSize) {
    SLUICE_ASSERT(localSize > 0, "groupCount: local size must be positive");
    const std::uint64_t groups = (items + localSize - 1) / localSize;
    SLUICE_ASSERT(groups <= 0xffffffffu, "groupCount: more than 2^32 - 1 groups");
    return static_cast<std::uint32_t>(groups);
}

glm::uvec3 groupCount(glm::uvec3 items, glm::uvec3 localSize) {
    return {groupCount(items.x, localSize.x), groupCount(items.y, localSize.y),
            groupCount(items.z, localSize.z)};
}

std::string assembleShaderSource(std::string_view source, std::span<const ShaderDefine> defines) {
    std::string defineLines;
    for (const auto& define : defines) {
        SLUICE_ASSERT(isIdentifier(define.name), "ShaderDefine name must be a GLSL identifier");
        SLUICE_ASSERT(define.value.find('\n') == std::string::npos,
                      "ShaderDefine value must be one line");
        defineLines += "#define " + define.name + " " + define.value + "\n";
    }

    // Find the #version line; everything before it can only be comments and blank lines.
    std::size_t lineStart = 0;
    int lineNumber = 1;
    while (lineStart < source.size()) {
        std::size_t lineEnd = source.find('\n', lineStart);
        std::size_t next = lineEnd == std::string_view::npos ? source.size() : lineEnd + 1;
        if (isVersionLine(source.substr(lineStart, next - lineStart))) {
            std::string text(source.substr(0, next));
            if (lineEnd == std::string_view::npos)
                text += '\n';
            // GLSL 4.50 #line N: the following line is line N (Mesa and NVIDIA agree).
            text += defineLines + "#line " + std::to_string(lineNumber + 1) + "\n";
            text += source.substr(next);
            return text;
        }
        lineStart = next;
        ++lineNumber;
    }
    std::string text = "#version 450 core\n" + defineLines + "#line 1\n";
    text += source;
    return text;
}

Result<Program> Program::compute(std::string_view name, std::string_view source,
                                 std::span<const ShaderDefine> defines) {
    return compute(name, source, defines, false);
}

Result<Program> Program::compute(std::string_view name, std::string_view source,
                                 std::span<const ShaderDefine> defines, bool retrievable) {
    Result<Program> program = [&]() -> Result<Program> {
        DebugMute mute; // failures come back as values, not as debug-output errors
        auto shader = compileStage(GL_COMPUTE_SHADER, name, source, defines);
        if (!shader)
            return shader.error();
        const std::array<GLuint, 1> shaders{*shader};
        return link(name, shaders, true, retrievable);
    }();
    failOnDebugErrors("Program::compute");
    return program;
}

Result<Program> Program::graphics(std::string_view name, std::string_view vertexSource,
                                  std::string_view fragmentSource,
                                  std::span<const ShaderDefine> defines) {
    Result<Program> program = [&]() -> Result<Program> {
        DebugMute mute;
        auto vertex = compileStage(GL_VERTEX_SHADER, name, vertexSource, defines);
        if (!vertex)
            return vertex.error();
        auto fragment = compileStage(GL_FRAGMENT_SHADER, name, fragmentSource, defines);
        if (!fragment) {
            glDeleteShader(*vertex);
            return fragment.error();
        }
        const std::array<GLuint, 2> shaders{*vertex, *fragment};
        return link(name, shaders, false);
    }();
    failOnDebugErrors("Program::graphics");
    return program;
}

Result<Program> Program::link(std::string_view name, std::span<const GLuint> shaders,
                              bool isCompute, bool retrievable) {
    Program program;
    program.m_id = glCreateProgram();
    program.m_name = std::string(name);
    if (retrievable) // so that binary() may be asked for (ProgramCache)
        glProgramParameteri(program.m_id, GL_PROGRAM_BINARY_RETRIEVABLE_HINT, GL_TRUE);
    for (GLuint shader : shaders)
        glAttachShader(program.m_id, shader);
    glLinkProgram(program.m_id);
    for (GLuint shader : shaders) {
        glDetachShader(program.m_id, shader);
        glDeleteShader(shader);
    }
    GLint status = GL_FALSE;
    glGetProgramiv(program.m_id, GL_LINK_STATUS, &status);
    if (status != GL_TRUE)
        return fail(ErrorCode::ShaderLink,
                    std::string(name) + " does not link:\n" + programLog(program.m_id));
    program.queryInterface(isCompute);
    return program;
}

void Program::queryInterface(bool isCompute) {
    if (isCompute) {
        GLint size[3] = {0, 0, 0};
        glGetProgramiv(m_id, GL_COMPUTE_WORK_GROUP_SIZE, size);
        m_localSize = glm::uvec3(size[0], size[1], size[2]);
        for (GLuint axis = 0; axis < 3; ++axis) {
            GLint maxGroups = 0;
            glGetIntegeri_v(GL_MAX_COMPUTE_WORK_GROUP_COUNT, axis, &maxGroups);
            m_maxGroups[static_cast<int>(axis)] = static_cast<std::uint32_t>(maxGroups);
        }
    }
    GLint count = 0;
    glGetProgramInterfaceiv(m_id, GL_UNIFORM, GL_ACTIVE_RESOURCES, &count);
    GLint maxLength = 0;
    glGetProgramInterfaceiv(m_id, GL_UNIFORM, GL_MAX_NAME_LENGTH, &maxLength);
    std::string buffer(static_cast<std::size_t>(std::max(maxLength, 1)), '\0');
    for (GLint i = 0; i < count; ++i) {
        const GLenum property = GL_LOCATION;
        GLint loc = -1;
        glGetProgramResourceiv(m_id, GL_UNIFORM, static_cast<GLuint>(i), 1, &property, 1, nullptr,
                               &loc);
        if (loc < 0)
            continue; // a member of a uniform block
        GLsizei length = 0;
        glGetProgramResourceName(m_id, GL_UNIFORM, static_cast<GLuint>(i), maxLength, &length,
                                 buffer.data());
        std::string name = buffer.substr(0, static_cast<std::size_t>(length));
        if (name.size() > 3 && name.ends_with("[0]"))
            m_uniforms.emplace_back(name.substr(0, name.size() - 3), loc);
        m_uniforms.emplace_back(std::move(name), loc);
    }
    m_groupOffsetLocation = location(shared::kGroupOffsetUniform);
}

Result<Program> Program::computeFromBinary(std::string_view name, const ProgramBinary& binary) {
    Result<Program> program = [&]() -> Result<Program> {
        DebugMute mute; // a refused binary is an answer, not a debug-output error
        Program out;
        out.m_id = glCreateProgram();
        out.m_name = std::string(name);
        glProgramParameteri(out.m_id, GL_PROGRAM_BINARY_RETRIEVABLE_HINT, GL_TRUE);
        glProgramBinary(out.m_id, binary.format, binary.bytes.data(),
                        static_cast<GLsizei>(binary.bytes.size()));
        GLint status = GL_FALSE;
        glGetProgramiv(out.m_id, GL_LINK_STATUS, &status);
        if (status != GL_TRUE)
            return fail(ErrorCode::ShaderLink, std::string(name) +
                                                   ": the driver refused the program binary:\n" +
                                                   programLog(out.m_id));
        out.queryInterface(true);
        return out;
    }();
    failOnDebugErrors("Program::computeFromBinary");
    return program;
}

ProgramBinary Program::binary() const {
    ProgramBinary out;
    GLint length = 0;
    glGetProgramiv(m_id, GL_PROGRAM_BINARY_LENGTH, &length);
    if (length <= 0)
        return out;
    out.bytes.resize(static_cast<std::size_t>(length));
    GLsizei written = 0;
    glGetProgramBinary(m_id, length, &written, &out.format, out.bytes.data());
    out.bytes.resize(static_cast<std::size_t>(std::max(written, 0)));
    return out;
}

GLint Program::location(std::string_view name) const {
    for (const auto& [uniformName, location] : m_uniforms)
        if (uniformName == name)
            return location;
    return -1;
}

bool Program::hasUniform(std::string_view name) const {
    return location(name) >= 0;
}

void Program::set(std::string_view name, float value) const {
    if (GLint loc = location(name); loc >= 0)
        glProgramUniform1f(m_id, loc, value);
}
void Program::set(std::string_view name, std::int32_t value) const {
    if (GLint loc = location(name); loc >= 0)
        glProgramUniform1i(m_id, loc, value);
}
void Program::set(std::string_view name, std::uint32_t value) const {
    if (GLint loc = location(name); loc >= 0)
        glProgramUniform1ui(m_id, loc, value);
}
void Program::set(std::string_view name, glm::vec2 value) const {
    if (GLint loc = location(name); loc >= 0)
        glProgramUniform2f(m_id, loc, value.x, value.y);
}
void Program::set(std::string_view name, glm::vec3 value) const {
    if (GLint loc = location(name); loc >= 0)
        glProgramUniform3f(m_id, loc, value.x, value.y, value.z);
}
void Program::set(std::string_view name, glm::vec4 value) const {
    if (GLint loc = location(name); loc >= 0)
        glProgramUniform4f(m_id, loc, value.x, value.y, value.z, value.w);
}
void Program::set(std::string_view name, glm::ivec3 value) const {
    if (GLint loc = location(name); loc >= 0)
        glProgramUniform3i(m_id, loc, value.x, value.y, value.z);
}
void Program::set(std::string_view name, glm::uvec3 value) const {
    if (GLint loc = location(name); loc >= 0)
        glProgramUniform3ui(m_id, loc, value.x, value.y, value.z);
}
void Program::set(std::string_view name, const glm::mat4& value) const {
    if (GLint loc = location(name); loc >= 0)
        glProgramUniformMatrix4fv(m_id, loc, 1, GL_FALSE, &value[0][0]);
}
void Program::set(std::string_view name, std::span<const float> values) const {
    if (GLint loc = location(name); loc >= 0)
        glProgramUniform1fv(m_id, loc, GLsizei(values.size()), values.data());
}

void Program::use() const {
    glUseProgram(m_id);
}

void Program::dispatch(glm::uvec3 groups) const {
    SLUICE_ASSERT(m_localSize.x > 0, "Program::dispatch on a program without a compute shader");
    SLUICE_ASSERT(groups.x <= m_maxGroups.x && groups.y <= m_maxGroups.y &&
                      groups.z <= m_maxGroups.z,
                  "Program::dispatch: more groups than GL_MAX_COMPUTE_WORK_GROUP_COUNT; "
                  "use dispatchChunked");
    glUseProgram(m_id);
    if (m_groupOffsetLocation >= 0)
        glProgramUniform3ui(m_id, m_groupOffsetLocation, 0, 0, 0);
    glDispatchCompute(groups.x, groups.y, groups.z);
    failOnDebugErrors("Program::dispatch");
}

std::uint32_t Program::dispatchChunked(glm::uvec3 groups,
                                       std::uint64_t maxGroupsPerDispatch) const {
    SLUICE_ASSERT(m_localSize.x > 0, "dispatchChunked on a program without a compute shader");
    SLUICE_ASSERT(maxGroupsPerDispatch > 0, "dispatchChunked: maxGroupsPerDispatch must be > 0");
    if (groups.x == 0 || groups.y == 0 || groups.z == 0)
        return 0;
    const std::uint64_t total = std::uint64_t{groups.x} * groups.y * groups.z;
    if (total <= maxGroupsPerDispatch && glm::all(glm::lessThanEqual(groups, m_maxGroups))) {
        dispatch(groups);
        return 1;
    }
    SLUICE_ASSERT(m_groupOffsetLocation >= 0,
                  "dispatchChunked: the shader must index with SLUICE_GLOBAL_ID "
                  "(shared/ChunkedDispatch.h) to be split");

    // Chunk shape: as many whole x rows as fit, then whole xy slabs; each axis also within
    // the GL limit, so chunking also runs grids larger than one dispatch may be.
    auto fit = [](std::uint64_t want, std::uint64_t budget, std::uint32_t limit) {
        return static_cast<std::uint32_t>(std::max<std::uint64_t>(
            1, std::min<std::uint64_t>({want, budget, std::uint64_t{limit}})));
    };
    glm::uvec3 chunk;
    chunk.x = fit(groups.x, maxGroupsPerDispatch, m_maxGroups.x);
    chunk.y = fit(groups.y, maxGroupsPerDispatch / chunk.x, m_maxGroups.y);
    chunk.z =
        fit(groups.z, maxGroupsPerDispatch / (std::uint64_t{chunk.x} * chunk.y), m_maxGroups.z);

    glUseProgram(m_id);
    std::uint32_t dispatches = 0;
    for (std::uint32_t z = 0; z < groups.z; z += std::min(chunk.z, groups.z - z)) {
        for (std::uint32_t y = 0; y < groups.y; y += std::min(chunk.y, groups.y - y)) {
            for (std::uint32_t x = 0; x < groups.x; x += std::min(chunk.x, groups.x - x)) {
                const glm::uvec3 size = glm::min(chunk, groups - glm::uvec3(x, y, z));
                glProgramUniform3ui(m_id, m_groupOffsetLocation, x, y, z);
                glDispatchCompute(size.x, size.y, size.z);
                // Hand each chunk to the GPU now rather than as one long batch.
                glFlush();
                ++dispatches;
            }
        }
    }
    failOnDebugErrors("Program::dispatchChunked");
    return dispatches;
}

Program::Program(Program&& other) noexcept
    : m_id(std::exchange(other.m_id, 0)), m_name(std::move(other.m_name)),
      m_localSize(other.m_localSize), m_maxGroups(other.m_maxGroups),
      m_uniforms(std::move(other.m_uniforms)), m_groupOffsetLocation(other.m_groupOffsetLocation) {}

Program& Program::operator=(Program&& other) noexcept {
    if (this != &other) {
        release();
        m_id = std::exchange(other.m_id, 0);
        m_name = std::move(other.m_name);
        m_localSize = other.m_localSize;
        m_maxGroups = other.m_maxGroups;
        m_uniforms = std::move(other.m_uniforms);
        m_groupOffsetLocation = other.m_groupOffsetLocation;
    }
    return *this;
}

Program::~Program() {
    release();
}

void Program::release() {
    if (m_id != 0)
        glDeleteProgram(m_id);
    m_id = 0;
}

} // namespace sluice::gpu
