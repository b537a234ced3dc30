// GoogleTest expectations on glm vectors, component by component, so a failure names the axis.
#pragma once

#include <glm/vec3.hpp>
#include <gtest/gtest.h>

namespace sluice::test {

/// Expects |a - b| <= tol on each of x, y and z.
inline void expectVecNear(glm::vec3 a, glm::vec3 b, float tol) {
    EXPECT_NEAR(a.x, b.x, tol);
    EXPECT_NEAR(a.y, b.y, tol);
    EXPECT_NEAR(a.z, b.z, tol);
}

} // namespace sluice::test
