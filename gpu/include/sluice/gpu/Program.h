// GLSL programs: compute (and vertex/fragment) compilation with info logs, uniforms, dispatch.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "sluice/format/support/Result.h"
#include "sluice/gpu/Gl.h"

namespace sluice::gpu {

/// A `#define name value` line injected into a shader after its #version line.
struct ShaderDefine {
    std::string name;
    std::string value;
};

/// Number of work groups of `localSize` invocations that cover `items` (rounds up).
/// Precondition: localSize > 0; the result fits in 32 bits.
std::uint32_t groupCount(std::uint64_t items, std::uint32_t localSize);
/// Per-axis groupCount for a 3D grid of `items` (e.g. voxels) and a 3D local size.
glm::uvec3 groupCount(glm::uvec3 items, glm::uvec3 localSize);

/// The text handed to the GLSL compiler for `source`. If `source` has no #version line, it gets
/// "#version 450 core", then the defines, then "#line 1", so compiler messages keep the line
/// numbers of `source`. If it has one, the defines and a #line follow that line.
std::string assembleShaderSource(std::string_view source, std::span<const ShaderDefine> defines);

/// A linked program as the driver's binary (glGetProgramBinary), valid only on the same driver.
struct ProgramBinary {
    GLenum format = 0;            ///< the driver's binary format
    std::vector<std::byte> bytes; ///< the binary itself
};

/// A linked GL program (RAII, move-only). The object is a handle: const methods still change GL
/// state (uniforms, the bound program). Needs the context that created it to be current.
class Program {
public:
    /// Compiles and links a compute shader. `name` appears in error messages (use the file
    /// name). ShaderCompile / ShaderLink carry the name and the driver's info log.
    static Result<Program> compute(std::string_view name, std::string_view source,
                                   std::span<const ShaderDefine> defines = {});
    /// Compiles and links a vertex + fragment pair, for rendering.
    static Result<Program> graphics(std::string_view name, std::string_view vertexSource,
                                    std::string_view fragmentSource,
                                    std::span<const ShaderDefine> defines = {});

    /// A compute program from a binary that binary() gave: no compiling or linking. ShaderLink
    /// when the driver refuses it (another driver or version, damaged bytes); never asserts on
    /// its bytes.
    static Result<Program> computeFromBinary(std::string_view name, const ProgramBinary& binary);

    Program() = default; ///< empty: id() == 0
    Program(Program&& other) noexcept;
    Program& operator=(Program&& other) noexcept;
    Program(const Program&) = delete;
    Program& operator=(const Program&) = delete;
    ~Program();

    GLuint id() const { return m_id; }
    const std::string& name() const { return m_name; }
    /// Local work-group size declared by a compute shader [invocations]; zero for graphics.
    glm::uvec3 localSize() const { return m_localSize; }

    /// glUseProgram.
    void use() const;

    /// The linked program as the driver's binary; empty bytes when the driver gives none.
    ProgramBinary binary() const;

    /// Uniform setters by name (glProgramUniform*, locations cached at link time). Unknown or
    /// optimized-away names are ignored, as GL ignores location -1.
    void set(std::string_view name, float value) const;
    void set(std::string_view name, std::int32_t value) const;
    void set(std::string_view name, std::uint32_t value) const;
    void set(std::string_view name, glm::vec2 value) const;
    void set(std::string_view name, glm::vec3 value) const;
    void set(std::string_view name, glm::vec4 value) const;
    void set(std::string_view name, glm::ivec3 value) const;
    void set(std::string_view name, glm::uvec3 value) const;
    void set(std::string_view name, const glm::mat4& value) const;
    /// A float array uniform from its first element (`name` without "[0]"); at most the
    /// array's length of values.
    void set(std::string_view name, std::span<const float> values) const;

    /// Binds this program and runs glDispatchCompute(groups). Resets the chunk offset uniform
    /// (shared/ChunkedDispatch.h) to zero if the shader has it. Precondition: a compute program;
    /// groups within GL_MAX_COMPUTE_WORK_GROUP_COUNT. Zero groups on an axis does nothing.
    void dispatch(glm::uvec3 groups) const;
    void dispatch(std::uint32_t groupsX) const { dispatch(glm::uvec3(groupsX, 1, 1)); }

    /// Runs the same work as dispatch(groups) as several dispatches of at most
    /// `maxGroupsPerDispatch` groups each (boxes: whole x rows, then xy slabs), with a glFlush
    /// after each, so no single dispatch runs long enough to stall the GPU or trip a watchdog.
    /// The shader must index with SLUICE_GLOBAL_ID from shared/ChunkedDispatch.h. Returns the
    /// number of dispatches issued. Precondition: maxGroupsPerDispatch > 0; the shader declares
    /// the offset uniform if more than one dispatch is needed.
    std::uint32_t dispatchChunked(glm::uvec3 groups, std::uint64_t maxGroupsPerDispatch) const;

    /// @name For tests only
    /// Inspection hooks for the test suites; the libraries and programs do not call them.
    /// @{

    /// Whether an active (not optimized away) uniform of this name exists; array uniforms
    /// answer to "name" and "name[0]".
    bool hasUniform(std::string_view name) const;

    /// @}

private:
    friend class ProgramCache; // compiles with the binary-retrievable hint
    static Result<Program> compute(std::string_view name, std::string_view source,
                                   std::span<const ShaderDefine> defines, bool retrievable);
    static Result<Program> link(std::string_view name, std::span<const GLuint> shaders,
                                bool isCompute, bool retrievable = false);
    void queryInterface(bool isCompute);
    GLint location(std::string_view name) const;
    void release();

    GLuint m_id = 0;
    std::string m_name;
    glm::uvec3 m_localSize{0};
    glm::uvec3 m_maxGroups{0};
    std::vector<std::pair<std::string, GLint>> m_uniforms; // few per program: linear search
    GLint m_groupOffsetLocation = -1;
};

} // namespace sluice::gpu
