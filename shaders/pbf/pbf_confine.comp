// Vorticity confinement and XSPH viscosity (Macklin & Mueller 2013, eq. 16, 17; docs/pbf.md 6),
// both from the velocities the solve ended with (pbf_delta.comp), written to the other velocity
// buffer.
#version 450 core

#define PBF_NEIGHBOUR_PASS 1
#include "glsl/PbfGlsl.h"

layout(local_size_x = kPbfLocalSize) in;

layout(std430, binding = kBindPosIn) readonly buffer PosIn { vec4 pos[]; };
layout(std430, binding = kBindVelIn) readonly buffer VelIn { vec4 vel[]; };
layout(std430, binding = kBindVelOut) writeonly buffer VelOut { vec4 velOut[]; };
layout(std430, binding = kBindOmega) readonly buffer Omega { vec4 omega[]; };
layout(std430, binding = kBindPredStart) readonly buffer PredStart { vec4 predStart[]; };
layout(std430, binding = kBindCellStart) readonly buffer CellStart { uint cellStart[]; };
layout(std430, binding = kBindNeighbourMask) readonly buffer Mask { uint neighbourMask[]; };

uniform uint withVorticity; // 0: omega was not computed this substep

void main() {
    uint i = PBF_PARTICLE;
    pbfLane = PBF_LANE;
    bool live = i < PBF_LIVE;
#if PBF_LANES == 1
    if (!live)
        return; // one lane: no barriers below
#endif
    vec3 vi = live ? vel[i].xyz : vec3(0.0);
    vec3 wi = live && withVorticity != 0u ? omega[i].xyz : vec3(0.0);
    vec3 eta = vec3(0.0);
    vec3 blend = vec3(0.0);
    if (live) {
        vec3 xi = pos[i].xyz;
        float wiLen = length(wi);
        PBF_NEIGHBOURS_BEGIN(predStart, neighbourMask, pos, i, xi)
            if (withVorticity != 0u)
                eta += (length(PBF_OMEGA_AT(omega, j).xyz) - wiLen) * spikyGrad(d, q2);
            blend += (PBF_VEL_AT(vel, j).xyz - vi) * poly6(q2);
        PBF_NEIGHBOURS_END
    }
    // Every lane's share (uniform: all reach the barriers).
    eta = pbfLaneSum(vec4(eta, 0.0)).xyz;
    blend = pbfLaneSum(vec4(blend, 0.0)).xyz;
    if (!live || pbfLane != 0u)
        return;
    eta *= PBF_VOLUME;
    float etaLen = length(eta);
    vec3 n = etaLen >= 1e-12 ? eta / etaLen : vec3(0.0);
    vec3 v = vi + PBF_DT * P.vorticity * cross(n, wi) + P.xsph * PBF_VOLUME * blend;
    velOut[i] = vec4(v, vel[i].w);
}
