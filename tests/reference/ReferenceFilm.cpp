// The CPU reference's film model (docs/bodies.md, "The film under a body"), as
// shaders/pbf/pbf_bodies.comp (filmReaction, takeFilmReaction), glsl/BodyContactsGlsl.h
// (sealedShare) and glsl/FilmGlsl.h (surfaceWordOf, surfaceLevel) do it, in double.
#include "ReferencePbf.h"

#include <algorithm>
#include <cmath>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

namespace sluice::ref {

namespace {

constexpr double kSurfaceUnits = 65536.0;

glm::dvec3 upOf(glm::vec3 gravity) {
    const double g = glm::length(glm::dvec3(gravity));
    return g > 0.0 ? -glm::dvec3(gravity) / g : glm::dvec3(0.0, 1.0, 0.0);
}

} // namespace

double ReferencePbf::sealedBand() const {
    const double h = double(m_c.h), r = double(m_c.radius);
    return h + double(shared::kSealedBandRadii) * r;
}

double ReferencePbf::rimBand() const {
    return sealedBand() + double(m_c.radius);
}

bool ReferencePbf::pointOverSolid(const Body& body, const glm::vec4& point, double band, float t1,
                                  PointOverSolid& out) const {
    out.world = body.pose.toWorld(glm::vec3(point));
    out.gap = nearestSolidWithin(out.world, band, t1, out.solidNormal);
    if (!(out.gap < band))
        return false;
    const format::SdfSampler& sampler = m_colliders[body.collider].sampler;
    const glm::dvec3 grad(body.pose.rotation *
                          glm::vec3(gradientInTheGpusCell(sampler, glm::vec3(point))));
    if (!(glm::length(grad) > 0.0))
        return false;
    out.normal = glm::normalize(grad);
    const double scale = body.pose.scale;
    out.area = double(point.w) * scale * scale;
    return true;
}

// Each compressed particle's height in the water column over each body, maxed into the body's
// level word (FilmGlsl.h, surfaceWordOf), once a substep at the first iteration.
void ReferencePbf::recordSurface(glm::vec3 x) {
    const glm::dvec3 up = upOf(m_params.gravity);
    const double h = double(m_c.h);
    for (Body& b : m_bodies) {
        const glm::dvec3 d = glm::dvec3(x) - glm::dvec3(b.centerOfMass);
        const double height = glm::dot(d, up);
        const glm::dvec3 across = d - height * up;
        const double reach = b.boundRadius + h;
        if (glm::dot(across, across) >= reach * reach)
            continue;
        const auto word =
            std::uint32_t(std::clamp(height + surfaceBase(b), 0.0, 4000.0 * h) / h * kSurfaceUnits);
        b.surface = std::max(b.surface, word);
    }
}

// The faces over a solid within the rim band get the water's pressure at their depth under the
// level across the solid, its moment along their own normals (weights fading out over the
// sealed band's last spacing); the water under them is topped up to it, or scaled down to it
// with what is taken off kept for finishBodySubstep's takeStopping.
void ReferencePbf::addFilm(Body& body, float t1) {
    const double g = glm::length(glm::dvec3(m_params.gravity));
    if (body.surface == 0 || !(g > 0.0))
        return;
    const glm::dvec3 up = upOf(m_params.gravity);
    const double h = double(m_c.h), r = double(m_c.radius);
    const glm::dvec3 c(body.centerOfMass);
    const double level =
        glm::dot(c, up) - surfaceBase(body) + double(body.surface) / kSurfaceUnits * h + 2.0 * r;
    const double band = rimBand(), sealedEdge = sealedBand();
    glm::dvec3 sealed(0.0), turn(0.0);
    double heads = 0.0;
    for (const glm::vec4& point : body.contactPoints) {
        PointOverSolid p;
        if (!pointOverSolid(body, point, band, t1, p))
            continue;
        const glm::dvec3 normal = p.normal, solidNormal = p.solidNormal;
        const double facing = glm::dot(normal, solidNormal);
        if (!(facing < -0.5))
            continue;
        const glm::vec3 w = p.world;
        const double head = p.area * std::max(0.0, level - glm::dot(glm::dvec3(w), up));
        const double weight = std::clamp((sealedEdge - p.gap) / (2.0 * r), 0.0, 1.0);
        heads += -facing * head;
        sealed += weight * head * facing * solidNormal;
        turn += glm::cross(glm::dvec3(w) - c, weight * head * normal);
    }
    const double sealedLength = glm::length(sealed);
    if (!(sealedLength > 0.0) || !(heads > 0.0))
        return;
    const glm::dvec3 along = sealed / sealedLength;
    const double share = std::min(1.0, sealedLength / heads);
    const double given = glm::dot(body.underDx, along);
    const double dt = double(m_c.dt);
    const double expected =
        double(shared::kFilmAreaShare) * g * dt * dt / double(m_c.volume) * heads;
    if (given < expected) {
        const double add = (expected - given) * share;
        body.sumDx += add * along;
        body.sumMoment += add / sealedLength * turn;
    } else if (given > expected) {
        const double cut = (given - expected) / given * share;
        body.filmDx = cut * body.underDx;
        body.filmMoment = cut * body.underMoment;
        body.sumDx -= body.filmDx;
        body.sumMoment -= body.filmMoment;
    }
}

// The level word's offset under the body's centre (FilmGlsl.h, surfaceBase) [m].
double ReferencePbf::surfaceBase(const Body& body) const {
    return 2.0 * body.boundRadius + 4.0 * double(m_c.h);
}

// An impulse (and angular impulse) that may only stop the body (pbf_bodies.comp, takeStopping):
// the share of it that ends the approach along it beyond `allowed` [m/s], at the centre or,
// `atPoint`, at the point of its line of action nearest the centre, with that point's velocity
// and the body's effective mass there; the motion takes it, the force and torque `share` of it.
void ReferencePbf::takeStopping(Body& body, glm::dvec3 impulse, glm::dvec3 angular, double allowed,
                                bool atPoint, double share, BodyMotion& motion) {
    const double len = glm::length(impulse);
    if (!(len > 0.0) || !(body.mass > 0.0))
        return;
    const double dt = m_c.dt;
    const glm::dvec3 n = impulse / len;
    double part = 0.0;
    if (atPoint) {
        const glm::dvec3 at = glm::cross(impulse, angular) / (len * len);
        const glm::dvec3 turn = glm::cross(at, n);
        const double invMassAt = 1.0 / body.mass + glm::dot(turn, body.invInertia * turn);
        const double approach = -glm::dot(motion.v + glm::cross(motion.w, at), n) - allowed;
        part = approach > 0.0 ? std::min(1.0, approach / (invMassAt * len)) : 0.0;
    } else {
        const double approach = -glm::dot(motion.v, n) - allowed;
        part = approach > 0.0 ? std::min(1.0, approach * body.mass / len) : 0.0;
    }
    motion.v += part * impulse / body.mass;
    motion.w += part * (body.invInertia * angular);
    body.force += share * part * impulse / dt;
    body.torque += share * part * angular / dt;
}

} // namespace sluice::ref
