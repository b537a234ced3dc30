// Martin & Moyce (1952) dam-break surge front, the classic check for free-surface solvers.
//
// J. C. Martin and W. J. Moyce, "An experimental study of the collapse of liquid columns on a
// rigid horizontal plane", Phil. Trans. R. Soc. Lond. A 244 (1952) 312-324. Square-based
// column of width a and height 2a (n^2 = 2), a = 2.25 in; the front position Z = x / a against
// the time T = t sqrt(2 g / a). The points are the measured values as reproduced throughout the
// SPH and MPS literature (the Z steps of 2/9 are the half-inch marks on the tank floor).
#pragma once

#include <array>
#include <utility>

namespace sluice::testdata {

/// (T, Z) pairs, T = t sqrt(2 g / a), Z = front x / a.
inline constexpr std::array<std::pair<double, double>, 16> kMartinMoyceFront = {{
    {0.00, 1.00}, {0.41, 1.11}, {0.84, 1.22}, {1.19, 1.44}, {1.43, 1.67}, {1.63, 1.89},
    {1.83, 2.11}, {1.98, 2.33}, {2.20, 2.56}, {2.32, 2.78}, {2.51, 3.00}, {2.65, 3.22},
    {2.83, 3.44}, {2.98, 3.67}, {3.11, 3.89}, {3.33, 4.11},
}};

/// The experimental front Z at time T, linear between the measured points (T in [0, 3.33]).
inline double martinMoyceFront(double t) {
    const auto& d = kMartinMoyceFront;
    for (std::size_t i = 1; i < d.size(); ++i)
        if (t <= d[i].first) {
            const double u = (t - d[i - 1].first) / (d[i].first - d[i - 1].first);
            return d[i - 1].second + u * (d[i].second - d[i - 1].second);
        }
    return d.back().second;
}

} // namespace sluice::testdata
