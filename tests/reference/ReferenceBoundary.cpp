// CPU reference of the PBF substep: the solids in the solve (docs/pbf.md, "Boundary volume" and
// "Collision"; docs/bodies.md): boundary volume, the constraint and lambda of a particle, the
// correction with the boundary pushes, collisions and the clamp.
#include "ReferencePbf.h"

#include <algorithm>
#include <cmath>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

namespace sluice::ref {

// The gradient of the trilinear field at local point p, in the cell the GPU's float arithmetic
// puts p in (glsl/PbfGlsl.h, sampleCollider), the values and the derivative in double. A body's
// contact points lie on its grid's planes, where the cells on either side give different
// gradients (an edge point's normal is the face's on one side, the other face's on the other),
// and double arithmetic may round to the other cell.
glm::dvec3 gradientInTheGpusCell(const format::SdfSampler& sampler, glm::vec3 p) {
    const format::ColliderMeta& m = sampler.asset().meta;
    const glm::vec3 lo(m.origin);
    const float voxel = float(m.voxelSize);
    const glm::vec3 g = (glm::clamp(p, lo, glm::vec3(sampler.boxMax())) - lo) / voxel;
    const glm::vec3 cell = glm::clamp(glm::floor(g), glm::vec3(0.0f), glm::vec3(m.dims) - 2.0f);
    const glm::dvec3 t = glm::clamp(glm::dvec3(g - cell), 0.0, 1.0);
    double v[2][2][2];
    for (int a = 0; a < 2; ++a)
        for (int b = 0; b < 2; ++b)
            for (int c = 0; c < 2; ++c)
                v[a][b][c] = sampler.value(m.origin +
                                           (glm::dvec3(cell) + glm::dvec3(a, b, c)) * m.voxelSize);
    const double wx[2] = {1.0 - t.x, t.x}, wy[2] = {1.0 - t.y, t.y}, wz[2] = {1.0 - t.z, t.z};
    glm::dvec3 grad(0.0);
    for (int i = 0; i < 2; ++i)
        for (int j = 0; j < 2; ++j) {
            grad.x += wy[i] * wz[j] * (v[1][i][j] - v[0][i][j]);
            grad.y += wx[i] * wz[j] * (v[i][1][j] - v[i][0][j]);
            grad.z += wx[i] * wy[j] * (v[i][j][1] - v[i][j][0]);
        }
    return grad / m.voxelSize;
}

// docs/bodies.md, "Boundary volume": the part of the poly6 support behind a flat boundary at
// distance phi, B(phi) = k (1/2 - 315/256 F(u)), F(u) = u - 4u^3/3 + 6u^5/5 - 4u^7/7 + u^9/9,
// u = phi / h clamped to [-1, 1]. Evaluated in double, stored as float like the solver's.
float ReferencePbf::boundaryShare(float phi) const {
    const double u = std::clamp(double(phi) / double(m_c.h), -1.0, 1.0);
    const double u2 = u * u;
    const double F = u - 4.0 / 3.0 * u * u2 + 6.0 / 5.0 * u * u2 * u2 -
                     4.0 / 7.0 * u * u2 * u2 * u2 + 1.0 / 9.0 * u * u2 * u2 * u2 * u2;
    return float(double(m_c.boundaryScale) * (0.5 - 315.0 / 256.0 * F));
}

// B'(phi) = dB/dphi = -k 315/256 F'(u) / h, F'(u) = (1 - u^2)^4; 0 for |u| >= 1 [1/m].
float ReferencePbf::boundaryShareSlope(float phi) const {
    const double u = double(phi) / double(m_c.h);
    if (std::abs(u) >= 1.0)
        return 0.0f;
    const double a = 1.0 - u * u;
    return float(-double(m_c.boundaryScale) * 315.0 / 256.0 / double(m_c.h) * a * a * a * a);
}

// docs/pbf.md, "Boundary volume": the walls and the static and kinematic colliders (at their
// pose at t1) as boundary volume. Each domain face is a flat boundary r beyond the plane the
// centres are clamped to; the faces of an axis add, the axes combine as independent cuts,
// 1 - (1 - f_x)(1 - f_y)(1 - f_z). A collider adds the flat share at its phi. Adds the share
// to `boundary` and its gradient to `gradient`, in the solver's order of operations.
glm::vec4 ReferencePbf::solidBoundaryAt(glm::vec3 x) const {
    float boundary = 0.0f;
    glm::vec3 gradient(0.0f);
    addSolidBoundary(x, time(), boundary, gradient);
    return {gradient, boundary};
}

void ReferencePbf::addSolidBoundary(glm::vec3 x, float t1, float& boundary,
                                    glm::vec3& gradient) const {
    const float r = m_c.radius;
    const float h = m_c.h;
    if (m_hasDomain) {
        const glm::vec3 below = x - (m_domainMin + glm::vec3(r)) + r;
        const glm::vec3 above = (m_domainMax - glm::vec3(r)) - x + r;
        if (std::min({below.x, below.y, below.z, above.x, above.y, above.z}) < h) {
            const float k = m_c.boundaryScale;
            glm::vec3 open(1.0f), slope(0.0f);
            for (int a = 0; a < 3; ++a) {
                if (below[a] < h) {
                    open[a] -= boundaryShare(below[a]) / k;
                    slope[a] -= boundaryShareSlope(below[a]) / k;
                }
                if (above[a] < h) {
                    open[a] -= boundaryShare(above[a]) / k;
                    slope[a] += boundaryShareSlope(above[a]) / k;
                }
            }
            boundary += k * (1.0f - open.x * open.y * open.z);
            gradient -= k * slope * glm::vec3(open.y * open.z, open.x * open.z, open.x * open.y);
        }
    }
    for (const Collider& c : m_colliders) {
        if (c.body != kNoBody)
            continue;
        const rt::ColliderPose now = rt::colliderPose(c.placement, t1);
        const glm::vec3 q = now.toLocal(x);
        const float phi = now.scale * c.sampler.value(glm::dvec3(q));
        if (!(phi < h))
            continue;
        const glm::vec3 grad = now.rotation * glm::vec3(c.sampler.gradient(glm::dvec3(q)));
        const float gradLength = glm::length(grad);
        const bool mapped = !c.volumeMap.empty();
        // docs/pbf.md, "Volume maps": with a map, a point on a ridge of the field (no gradient)
        // outside the solid still gets its share, and the slope is the share's own gradient.
        if (!(gradLength > 0.0f || (mapped && phi >= 0.0f)))
            continue;
        float share = boundaryShare(phi);
        glm::vec3 slope =
            gradLength > 0.0f ? boundaryShareSlope(phi) * (grad / gradLength) : glm::vec3(0.0f);
        if (mapped) {
            slope = boundaryShareSlope(phi) * grad;
            glm::dvec3 mapGrad;
            const double more = volumeCorrection(c, glm::dvec3(q), mapGrad);
            share += m_c.boundaryScale * float(more);
            slope += m_c.boundaryScale / now.scale * (now.rotation * glm::vec3(mapGrad));
            if (!(share > 0.0f))
                continue;
        }
        boundary += share;
        gradient += slope;
    }
}

// phi_b at x, from the body's fluid-facing surface (bodyOffset inside its zero level set), and
// its outward unit world normal; false when the kernel does not reach the body (phi_b >= h) or
// the gradient is zero.
bool ReferencePbf::bodyBoundary(const Body& body, glm::vec3 x, float& phi,
                                glm::vec3& normal) const {
    const format::SdfSampler& sampler = m_colliders[body.collider].sampler;
    const glm::vec3 q = body.pose.toLocal(x);
    phi = body.pose.scale * sampler.value(glm::dvec3(q)) + m_bodyOffset;
    if (!(phi < m_c.h))
        return false;
    const glm::vec3 grad = body.pose.rotation * glm::vec3(sampler.gradient(glm::dvec3(q)));
    const float gradLength = glm::length(grad);
    if (!(gradLength > 0.0f))
        return false;
    normal = grad / gradLength;
    return true;
}

// Step 4.1 for particle i (eq. 1, 7, 8): its constraint and lambda from this iteration's
// kernel values, with the solids' and bodies' boundary volume (docs/pbf.md, "Boundary volume";
// docs/bodies.md). Stores both; returns C_i.
float ReferencePbf::constraintAndLambda(std::size_t i, const std::vector<float>& pairW,
                                        const std::vector<glm::vec3>& pairGrad, float t1) {
    const float V = m_c.volume;
    float wSum = W(0.0f);
    glm::vec3 gSum(0.0f);
    float gSq = 0.0f;
    for (std::uint32_t a = m_neighbourStart[i]; a < m_neighbourStart[i + 1]; ++a) {
        wSum += pairW[a];
        const glm::vec3 g = V * pairGrad[a];
        gSum += g;
        gSq += glm::dot(g, g);
    }
    // Solids fill part of the support and stiffen the particle's own gradient.
    float boundary = 0.0f;
    addSolidBoundary(m_predicted[i], t1, boundary, gSum);
    for (const Body& b : m_bodies) {
        float phi;
        glm::vec3 normal;
        if (!bodyBoundary(b, m_predicted[i], phi, normal))
            continue;
        boundary += boundaryShare(phi);
        gSum += boundaryShareSlope(phi) * normal;
    }
    const float rho = m_c.mass * wSum;
    const float C = std::max(rho / m_params.restDensity + boundary - 1.0f, 0.0f);
    m_constraint[i] = C;
    m_lambda[i] = -C / (gSq + glm::dot(gSum, gSum) + m_c.epsilon);
    return C;
}

// Step 4.4 for particle i: its correction dp applied, the solids' and the bodies' boundary
// pushes, the collisions in scene order and the clamp into the domain shrunk by r. Returns the
// new x*_i.
glm::vec3 ReferencePbf::applyCorrection(std::size_t i, glm::vec3 dp, glm::vec3 xOld, float t0,
                                        float t1) {
    const float r = m_c.radius;
    const glm::vec3 xi = m_predicted[i];
    const double band = rimBand();
    m_inRim = !m_bodies.empty() && nearestSolidWithin(xi, band, t1, m_rimNormal) < band;
    glm::vec3 x = xi + dp;
    if (!isFinite(x))
        x = xi; // a non-finite correction is dropped (step 4.4)
    // docs/pbf.md, "Boundary volume": the walls and static colliders push with the particle's
    // own lambda along their share's gradient at x*_i.
    float solidShare = 0.0f;
    glm::vec3 solidSlope(0.0f);
    addSolidBoundary(xi, t1, solidShare, solidSlope);
    const glm::vec3 solidPush = m_lambda[i] * solidSlope;
    if (isFinite(solidPush))
        x += solidPush;
    // docs/bodies.md: each body, a constraint partner of infinite mass, pushes with the
    // particle's own lambda along its normal at x*_i, and takes the reaction.
    for (Body& b : m_bodies) {
        float phi;
        glm::vec3 normal;
        if (!bodyBoundary(b, xi, phi, normal))
            continue;
        const glm::vec3 push = m_lambda[i] * boundaryShareSlope(phi) * normal;
        if (!isFinite(push))
            continue;
        x += push;
        addReaction(b, x, push);
        addRim(b, x, push);
    }
    if (!isFinite(x))
        x = xi;
    Pushed pushed;
    collide(x, xOld, t0, t1, pushed);
    if (!isFinite(x))
        x = xi;
    glm::vec3 clamped = x;
    if (m_hasDomain)
        for (int a = 0; a < 3; ++a) // std::max/min in this order keep a NaN a NaN
            clamped[a] = std::min(std::max(x[a], m_domainMin[a] + r), m_domainMax[a] - r);
    // docs/bodies.md, "Particles held against a wall": what the clamp undoes of a body's
    // push-out moves from the body's reaction to its held sums.
    if (pushed.body != kNoBody) {
        glm::vec3 back(0.0f);
        for (int a = 0; a < 3; ++a) {
            const float undone = clamped[a] - x[a];
            if (pushed.sum[a] * undone < 0.0f)
                back[a] =
                    std::copysign(std::min(std::abs(undone), std::abs(pushed.sum[a])), undone);
        }
        if (back != glm::vec3(0.0f)) {
            addReaction(m_bodies[pushed.body], clamped, back);
            addHeld(m_bodies[pushed.body], clamped, -back);
        }
    }
    return clamped;
}

void ReferencePbf::collide(glm::vec3& x, glm::vec3 xOld, float t0, float t1, Pushed& pushed) {
    const float r = m_c.radius;
    for (const Collider& c : m_colliders) {
        Body* body = c.body != kNoBody ? &m_bodies[c.body] : nullptr;
        const rt::ColliderPose now = body ? body->pose : rt::colliderPose(c.placement, t1);
        const glm::vec3 q = now.toLocal(x);
        float phi = now.scale * c.sampler.value(glm::dvec3(q));
        if (body)
            phi += m_bodyOffset; // its fluid-facing surface (docs/bodies.md, "Surface offset")
        if (!(phi < r))
            continue;
        const glm::vec3 grad = now.rotation * glm::vec3(c.sampler.gradient(glm::dvec3(q)));
        const float gradLength = glm::length(grad);
        if (!(gradLength > 0.0f))
            continue; // no direction to push along (a flat spot of the interpolant)
        const glm::vec3 normal = grad / gradLength;
        const glm::vec3 xBefore = x;
        x += (r - phi) * normal;
        // Friction: remove the slip relative to the collider's own motion of the contact point,
        // c = x - T(t) T(t + dt)^-1 x (0 for a body: it is held where it is).
        glm::vec3 carried(0.0f);
        if (!body) {
            const rt::ColliderPose before = rt::colliderPose(c.placement, t0);
            carried = x - before.toWorld(now.toLocal(x));
        }
        const glm::vec3 slip = (x - xOld) - carried;
        const glm::vec3 tangential = slip - glm::dot(slip, normal) * normal;
        x -= c.placement.friction * tangential;
        // A body takes the opposite of its push-out and friction together (docs/bodies.md,
        // "Reaction"), with the moment arm from where the particle ends (the same moment as from
        // where it started, since dx x dx = 0, up to rounding).
        if (body) {
            addReaction(*body, x, x - xBefore);
            addRim(*body, x, x - xBefore);
            if (pushed.body == kNoBody || pushed.body == c.body) {
                pushed.body = c.body;
                pushed.sum += x - xBefore;
            }
        }
    }
}

// docs/bodies.md, "Sealed contacts": how far x lies from the nearest domain wall's face or
// static collider's surface (at t1) when nearer than `limit` (else `limit`), and that solid's
// unit normal out of it.
double ReferencePbf::nearestSolidWithin(glm::vec3 x, double limit, float t1,
                                        glm::dvec3& normal) const {
    double gap = limit;
    normal = glm::dvec3(0.0);
    if (m_hasDomain)
        for (int a = 0; a < 3; ++a) {
            const double below = double(x[a]) - double(m_domainMin[a]);
            const double above = double(m_domainMax[a]) - double(x[a]);
            if (below < gap) {
                gap = below;
                normal = glm::dvec3(0.0);
                normal[a] = 1.0;
            }
            if (above < gap) {
                gap = above;
                normal = glm::dvec3(0.0);
                normal[a] = -1.0;
            }
        }
    for (const Collider& c : m_colliders) {
        if (c.body != kNoBody)
            continue;
        const rt::ColliderPose now = rt::colliderPose(c.placement, t1);
        const glm::dvec3 q(now.toLocal(x));
        const double phi = double(now.scale) * double(c.sampler.value(q));
        const glm::dvec3 grad(now.rotation * glm::vec3(c.sampler.gradient(q)));
        if (phi < gap && glm::length(grad) > 0.0) {
            gap = phi;
            normal = glm::normalize(grad);
        }
    }
    return gap;
}

// A push of the body on a particle of the rim (within the rim band of a solid at x*_i), which
// ends at x: across the solid (within 60 degrees of its normal), into the under sums, with its
// moment (the film model's, ReferenceFilm.cpp).
void ReferencePbf::addRim(Body& body, glm::vec3 x, glm::vec3 dx) {
    const double len = glm::length(glm::dvec3(dx));
    if (!m_inRim || !(len > 0.0) || !(std::abs(glm::dot(glm::dvec3(dx), m_rimNormal)) >= 0.5 * len))
        return;
    body.underDx += glm::dvec3(dx);
    body.underMoment += glm::cross(glm::dvec3(x) - glm::dvec3(body.centerOfMass), glm::dvec3(dx));
}

} // namespace sluice::ref
