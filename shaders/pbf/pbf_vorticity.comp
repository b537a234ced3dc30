// Vorticity omega_i = curl v by SPH (Macklin & Mueller 2013, eq. 15), for the confinement pass.
#version 450 core

#define PBF_NEIGHBOUR_PASS 1
#include "glsl/PbfGlsl.h"

layout(local_size_x = kPbfLocalSize) in;

layout(std430, binding = kBindPosIn) readonly buffer PosIn { vec4 pos[]; };
layout(std430, binding = kBindVelIn) readonly buffer VelIn { vec4 vel[]; };
layout(std430, binding = kBindOmega) writeonly buffer Omega { vec4 omega[]; };
layout(std430, binding = kBindPredStart) readonly buffer PredStart { vec4 predStart[]; };
layout(std430, binding = kBindCellStart) readonly buffer CellStart { uint cellStart[]; };
layout(std430, binding = kBindNeighbourMask) readonly buffer Mask { uint neighbourMask[]; };

void main() {
    uint i = PBF_PARTICLE;
    pbfLane = PBF_LANE;
    bool live = i < PBF_LIVE;
#if PBF_LANES == 1
    if (!live)
        return; // one lane: no barriers below
#endif
    vec3 w = vec3(0.0);
    if (live) {
        vec3 xi = pos[i].xyz;
        vec3 vi = vel[i].xyz;
        PBF_NEIGHBOURS_BEGIN(predStart, neighbourMask, pos, i, xi)
            // grad_j W(x_i - x_j) = gradW(x_j - x_i) = -gradW(d)
            w += cross(PBF_VEL_AT(vel, j).xyz - vi, -spikyGrad(d, q2));
        PBF_NEIGHBOURS_END
    }
    w = pbfLaneSum(vec4(w, 0.0)).xyz; // every lane's share (uniform: all reach the barriers)
    if (live && pbfLane == 0u)
        omega[i] = vec4(PBF_VOLUME * w, 0.0);
}
