// The trajectory table: header, rows, atomic write.
#include "output/BodiesCsv.h"

#include <cstdio>
#include <span>

#include "sluice/format/support/AtomicFile.h"

namespace sluice::rt {
namespace {

void appendNumber(std::string& out, double value) {
    char text[32];
    std::snprintf(text, sizeof text, ",%.9g", value);
    out += text;
}

void appendVec3(std::string& out, glm::vec3 v) {
    for (int axis = 0; axis < 3; ++axis)
        appendNumber(out, v[axis]);
}

/// RFC 4180: a field with a comma, a quote or a line break is quoted, its quotes doubled.
std::string csvField(const std::string& text) {
    if (text.find_first_of(",\"\r\n") == std::string::npos)
        return text;
    std::string out = "\"";
    for (char c : text) {
        if (c == '"')
            out += '"';
        out += c;
    }
    return out + '"';
}

} // namespace

std::string bodiesCsvHeader() {
    return "step,time,body,collider,asset,origin_x,origin_y,origin_z,centre_of_mass_x,"
           "centre_of_mass_y,centre_of_mass_z,orientation_x,orientation_y,orientation_z,"
           "orientation_w,linear_velocity_x,linear_velocity_y,linear_velocity_z,"
           "angular_velocity_x,angular_velocity_y,angular_velocity_z,submerged_share,force_x,"
           "force_y,force_z\n";
}

std::string bodiesCsvRows(const format::Scene& scene, std::uint64_t step, double time,
                          const std::vector<BodyState>& bodies) {
    std::string out;
    for (std::size_t i = 0; i < bodies.size(); ++i) {
        const BodyState& b = bodies[i];
        out += std::to_string(step);
        appendNumber(out, time);
        out += ',' + std::to_string(i) + ',' + std::to_string(b.collider) + ',';
        out += csvField(b.collider < scene.colliders.size()
                            ? format::colliderName(scene.colliders[b.collider])
                            : std::string());
        appendVec3(out, b.pose.translation);
        appendVec3(out, b.position);
        const glm::quat q = b.orientation;
        for (float component : {q.x, q.y, q.z, q.w})
            appendNumber(out, component);
        appendVec3(out, b.linearVelocity);
        appendVec3(out, b.angularVelocity);
        appendNumber(out, b.submergedShare);
        appendVec3(out, b.force);
        out += '\n';
    }
    return out;
}

void BodiesCsv::record(const format::Scene& scene, std::uint64_t step, double time,
                       const std::vector<BodyState>& bodies) {
    if (enabled())
        m_rows += bodiesCsvRows(scene, step, time, bodies);
}

Result<void> BodiesCsv::write() const {
    if (!enabled())
        return {};
    const std::string text = bodiesCsvHeader() + m_rows;
    return format::writeFileAtomic(m_path, std::as_bytes(std::span(text.data(), text.size())));
}

} // namespace sluice::rt
