#pragma once
// The specular-diffuse-specular scene (scenes/sds-mirrors.pbrt) and the closed form of its
// floor's luminance seen through the mirror, for the tests of the integrators that render it
// (sppm_test.cpp, vcm_test.cpp).
#include <cmath>
#include <string>
#include <vector>

#include "steradian/bsdf/fresnel.h"
#include "steradian/camera/camera.h"
#include "support/block_stats.h"

namespace sr::test {

// ---- the specular-diffuse-specular scene ---------------------------------------------------

// scenes/sds-mirrors.pbrt: a spot light of I = 1000 cd (inner cone 18 degrees) at (-0.5, 0, 3)
// aimed at the mirror M1 (plane x = -1.5), whose reflection lights a Lambertian floor (z = 0,
// reflectance 0.5) as from the light's mirror image P' = (-2.5, 0, 3); the camera sees the
// floor through the mirror M2 (plane y = 2.5). Both mirrors are conductors of eta = 0.2, k = 5
// at every wavelength. Vertical mirrors keep the sign of a ray's z, so light leaving the
// floor upwards never comes back to it: the luminance the camera sees along a ray that
// reflects off M2 at incidence cosine c2 and meets the floor at x is
//   Y = R(c2) (rho / pi) R(c1) I cos(theta) / d^2,
// d = |x - P'|, cos(theta) = 3 / d, c1 the incidence cosine of (x - P') on M1, R the
// conductor's Fresnel reflectance. The expected value of a pixel (box filter) is Y averaged
// over its area; we take the camera's own rays through 8 x 8 points of each pixel and
// intersect the two planes analytically.
constexpr double kPiD = 3.14159265358979323846;
constexpr double kI = 1000, kRho = 0.5, kEta = 0.2, kK = 5;
constexpr int kSdsRes = 64, kSdsBlock = 8;

/// The closed-form luminance along the camera ray through film point p, or -1 if the ray
/// does not reach the floor's lit interior through M2 (by at least `margin` from its edges
/// and inside the spot's inner cone).
inline double sds_expected(const Camera& cam, Point2 p, double margin) {
    const Ray r = cam.generate_ray(p, Point2(0.5f, 0.5f));
    const double o[3] = {r.o.x, r.o.y, r.o.z};
    double d[3] = {r.d.x, r.d.y, r.d.z};
    const double dl = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    for (double& v : d) v /= dl;
    if (!(d[1] > 0)) return -1;
    const double t = (2.5 - o[1]) / d[1];
    const double m[3] = {o[0] + t * d[0], 2.5, o[2] + t * d[2]};
    if (m[2] < 0 || m[2] > 5 || std::abs(m[0]) > 3) return -1;
    const double c2 = d[1];
    d[1] = -d[1];  // reflected off y = 2.5
    if (!(d[2] < 0)) return -1;
    const double s = -m[2] / d[2];
    const double x = m[0] + s * d[0], y = m[1] + s * d[1];
    if (x < -1.4 + margin || x > 2.5 - margin || y < -2 + margin || y > 2 - margin) return -1;
    // From the light's image to the floor point.
    const double v[3] = {x + 2.5, y, -3.0};
    const double dist = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    const double cos_theta = 3 / dist, c1 = v[0] / dist;
    // Inside the inner cone: the angle between the reflected axis (1, 0, -1)/sqrt(2) and v.
    const double cos_axis = (v[0] - v[2]) / (std::sqrt(2.0) * dist);
    if (cos_axis < std::cos(18 * kPiD / 180)) return -1;
    // Where the real ray meets M1 (x = -1.5): inside the mirror.
    const double u = 1 / v[0];  // from P', the fraction of v to reach x = -1.5
    const double zm = 3 + u * v[2], ym = u * v[1];
    if (zm < 0.3 || zm > 4 || std::abs(ym) > 2) return -1;
    const double r1 = fr_complex(Float(c1), Float(kEta), Float(kK));
    const double r2 = fr_complex(Float(c2), Float(kEta), Float(kK));
    return r2 * kRho / kPiD * r1 * kI * cos_theta / (dist * dist);
}

/// The expected block means (8 x 8 points per pixel), -1 for blocks not wholly inside.
inline std::vector<double> sds_expected_blocks(const Scene& scene, double margin) {
    const int nb = kSdsRes / kSdsBlock;
    std::vector<double> e(size_t(nb * nb), 0);
    for (int by = 0; by < nb; ++by)
        for (int bx = 0; bx < nb; ++bx) {
            double sum = 0;
            bool inside = true;
            for (int py = by * kSdsBlock; py < (by + 1) * kSdsBlock && inside; ++py)
                for (int px = bx * kSdsBlock; px < (bx + 1) * kSdsBlock && inside; ++px)
                    for (int j = 0; j < 8 && inside; ++j)
                        for (int i = 0; i < 8; ++i) {
                            const double v = sds_expected(
                                *scene.camera,
                                Point2(Float(px + (i + 0.5) / 8), Float(py + (j + 0.5) / 8)),
                                margin);
                            if (v < 0) {
                                inside = false;
                                break;
                            }
                            sum += v;
                        }
            e[size_t(by * nb + bx)] = inside ? sum / (kSdsBlock * kSdsBlock * 64) : -1;
        }
    return e;
}

inline std::string sds_scene(const std::string& integrator) {
    std::string s = read_text(std::string(STERADIAN_SOURCE_DIR) + "/scenes/sds-mirrors.pbrt");
    const size_t i = s.find("Integrator \"sppm\"");
    const size_t e = s.find("WorldBegin");
    EXPECT_NE(i, std::string::npos);
    return s.substr(0, i) + integrator + "\n" + s.substr(e);
}

}  // namespace sr::test
