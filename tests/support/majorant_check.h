#pragma once
// Checks that a medium's majorant grid bounds its density: the density at random points of
// the bounds against the majorant of the cell each falls in (as the DDA assigns cells).
#include <algorithm>

#include "steradian/media/medium.h"
#include "steradian/sampling/rng.h"

namespace sr::test {

struct MajorantCheck {
    int violations = 0;    ///< points where density(p) > the cell's majorant
    double largest = 0;    ///< the largest density met (a check that looked where it is)
};

/// n random points of the box [p0, p1] (seeded), density(p) against g's cell over them.
template <typename F>
MajorantCheck check_majorant(const MajorantGrid& g, Point3 p0, Point3 p1, F&& density, int n,
                             uint64_t seed) {
    Pcg32 rng(seed, 9);
    MajorantCheck r;
    const int res = g.res;
    for (int i = 0; i < n; ++i) {
        Point3 u(rng.next_float(), rng.next_float(), rng.next_float());
        double d = density(p0 + (p1 - p0) * u);
        r.largest = std::max(r.largest, d);
        int x = std::min(int(u.x * res), res - 1), y = std::min(int(u.y * res), res - 1),
            z = std::min(int(u.z * res), res - 1);
        if (d > g.at(x, y, z) * (1 + 1e-6)) ++r.violations;
    }
    return r;
}

}  // namespace sr::test
