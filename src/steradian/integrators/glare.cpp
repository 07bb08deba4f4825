#include "steradian/integrators/glare.h"

#include <cmath>
#include <filesystem>
#include <set>

#include <fmt/format.h>

#include "steradian/integrators/measure.h"
#include "steradian/lights/photometric/photometric.h"
#include "steradian/scene/scene.h"
#include "steradian/spectrum/spectrum.h"

namespace sr {

double guth_position_index(Vec3 to_source, Vec3 view, Vec3 up) {
    const double d = double(dot(to_source, view));
    if (d <= 0) return -1;
    if (d >= 1 - 1e-12) return 1;
    // The up direction made perpendicular to the view, as the formula presumes.
    Vec3 u = up - view * dot(up, view);
    const double ul = double(length(u));
    if (!(ul > 0)) return -1;
    const double sigma = std::acos(d) * 180 / kPi;
    const double c = std::min(1.0, std::abs(double(dot(to_source, u)) / ul) / std::sqrt(1 - d * d));
    const double tau = std::acos(c) * 180 / kPi;
    const double ln_p = (35.2 - 0.31889 * tau - 1.22 * std::exp(-2 * tau / 9)) * 1e-3 * sigma +
                        (21 + 0.26667 * tau - 0.002963 * tau * tau) * 1e-5 * sigma * sigma;
    return std::exp(ln_p);
}

double luminous_projected_area(const PhotometricData& d, Vec3 l) {
    // Semi-axes: x along the length (C0), y along the width (C90), z along the height.
    const double ax = d.length / 2, ay = d.width / 2, az = d.height / 2;
    const double lx = std::abs(double(l.x)), ly = std::abs(double(l.y)), lz = std::abs(double(l.z));
    // A convex body's projected area is half the sum over its faces of area |n . l|; for a
    // prism of an elliptical section (semi-axes p, q across the axis, length h) that is
    // pi p q |l_axis| for the ends and 2 h sqrt(p^2 l_q^2 + q^2 l_p^2) for the side.
    auto prism = [](double p, double q, double h, double l_axis, double l_p, double l_q) {
        return kPi * p * q * l_axis + 2 * h * std::sqrt(p * p * l_q * l_q + q * q * l_p * l_p);
    };
    switch (d.shape) {
        case LuminousShape::Point: return 0;
        case LuminousShape::Rectangular: return 4 * ax * ay * lz;
        case LuminousShape::RectangularWithLuminousSides:
            return 4 * (ax * ay * lz + ax * az * ly + ay * az * lx);
        case LuminousShape::Circular:
        case LuminousShape::Elliptical: return kPi * ax * ay * lz;
        case LuminousShape::VerticalCylinder:
        case LuminousShape::VerticalEllipticalCylinder:
            return prism(ax, ay, d.height, lz, lx, ly);
        case LuminousShape::HorizontalCylinderAlong:
        case LuminousShape::HorizontalEllipticalCylinderAlong:
            return prism(ay, az, d.length, lx, ly, lz);
        case LuminousShape::HorizontalCylinderPerpendicular:
        case LuminousShape::HorizontalEllipticalCylinderPerpendicular:
            return prism(ax, az, d.width, ly, lx, lz);
        case LuminousShape::Sphere:
        case LuminousShape::Ellipsoid:
            // An ellipsoid's shadow along l: pi sqrt((ay az lx)^2 + (ax az ly)^2 + (ax ay lz)^2).
            return kPi * std::sqrt(sqr(ay * az * lx) + sqr(ax * az * ly) + sqr(ax * ay * lz));
        case LuminousShape::VerticalCircleFacingHorizontal:
        case LuminousShape::VerticalEllipseFacingHorizontal: return kPi * ay * az * lx;
        case LuminousShape::VerticalCirclePerpendicular:
        case LuminousShape::VerticalEllipsePerpendicular: return kPi * ax * az * ly;
        case LuminousShape::Unknown: return 0;
    }
    return 0;
}

Point3 PhotometricLuminaire::centre() const {
    return profile->light_from_world.inverse().point(Point3(0, 0, 0));
}

Vec3 PhotometricLuminaire::nadir() const {
    const Vec3 n = profile->light_from_world.inverse().vector(Vec3(0, 0, -1));
    return length(n) > 0 ? normalize(n) : n;
}

std::vector<PhotometricLuminaire> photometric_luminaires(const Scene& scene) {
    std::vector<PhotometricLuminaire> out;
    std::set<const GoniometricEmission*> seen;
    for (const Light& light : scene.lights) {
        if (const auto* g = std::get_if<GoniometricLight>(&light)) {
            if (g->profile.data)  // (an image distribution has no file data)
                out.push_back({&g->profile,
                               double(g->scale) * double(spectrum_to_photometric(g->spectrum)),
                               false});
        } else if (const auto* a = std::get_if<DiffuseAreaLight>(&light)) {
            const GoniometricEmission* e = a->goniometric.get();
            if (e && e->profile.data && seen.insert(e).second)
                out.push_back({&e->profile,
                               double(e->scale) * double(spectrum_to_photometric(e->spectrum)),
                               true});
        }
    }
    return out;
}

GlareReading unified_glare_rating(const Scene& scene, Point3 eye, Vec3 view, Vec3 up,
                                  double e_ind, double e_ind_stderr) {
    GlareReading g;
    g.indirect_illuminance = e_ind;
    g.indirect_stderr = e_ind_stderr;
    g.background_luminance = e_ind / kPi;
    view = normalize(view);
    double sum = 0;
    bool omega_ok = true;
    for (const PhotometricLuminaire& c : photometric_luminaires(scene)) {
        const PhotometricData& data = *c.profile->data;
        GlareSource s;
        s.file = std::filesystem::path(data.source).filename().string();
        s.position = c.centre();
        Vec3 to_lum = s.position - eye;
        s.distance = double(length(to_lum));
        if (!(s.distance > 0)) {
            s.note = "at the eye";
            g.sources.push_back(s);
            continue;
        }
        const Vec3 dir = to_lum / Float(s.distance);
        // Towards the eye, in the luminaire's frame.
        const Vec3 l = c.profile->local(-dir);
        s.intensity = c.multiplier * data.intensity_direction(l.x, l.y, l.z);
        s.projected_area = luminous_projected_area(data, l);
        s.position_index = guth_position_index(dir, view, up);
        if (s.position_index < 0) {
            s.note = "behind the observer";
        } else if (!(s.projected_area > 0)) {
            s.note = data.shape == LuminousShape::Point
                         ? "no luminous opening in its file (a point): no luminance"
                         : "its luminous opening is edge-on to the eye";
        } else {
            // Visibility of the centre, stopped short of the opening itself.
            const double half_extent = 0.5 * std::max({data.width, data.length, data.height});
            Ray r{eye, dir, Float(std::max(0.0, s.distance - half_extent) * (1 - 1e-4))};
            if (r.t_max > 0 && scene.occluded(r)) {
                s.note = "hidden from the eye";
            } else if (!(s.intensity > 0)) {
                s.note = "no intensity towards the eye";
            } else {
                s.solid_angle = s.projected_area / sqr(s.distance);
                s.luminance = s.intensity / s.projected_area;
                s.term = sqr(s.luminance) * s.solid_angle / sqr(s.position_index);
                s.counted = true;
                sum += s.term;
                if (s.solid_angle < 3e-4 || s.solid_angle > 0.1) {
                    omega_ok = false;
                    s.note = fmt::format("solid angle {:.3g} sr outside CIE 117's 0.0003 to 0.1 sr",
                                         s.solid_angle);
                }
            }
        }
        g.sources.push_back(s);
    }
    if (!(sum > 0)) {
        g.note = "no luminaire with a luminous opening is in view: UGR undefined (reported as 0)";
    } else if (!(g.background_luminance > 0)) {
        g.note = "no indirect light at the eye (L_b = 0): UGR undefined (reported as 0)";
    } else {
        g.defined = true;
        g.ugr = 8 * std::log10(0.25 / g.background_luminance * sum);
        g.ugr_stderr = 8 / std::log(10.0) * e_ind_stderr / e_ind;
        g.in_range = omega_ok && g.ugr >= 10 && g.ugr <= 30;
        if (g.ugr < 10 || g.ugr > 30)
            g.note = "outside CIE 117's range of 10 to 30";
        else if (!omega_ok)
            g.note = "a luminaire's solid angle is outside CIE 117's range";
    }
    return g;
}

void apply_glare(const Scene& scene, MeasureResult& result) {
    for (MeterReading& rd : result.readings) {
        if (!rd.meter.glare) continue;
        rd.glare.clear();
        for (size_t k = 0; k < rd.values.size(); ++k) {
            GlareReading g = unified_glare_rating(scene, rd.meter.points[k], rd.meter.directions[k],
                                                  rd.meter.glare_up, rd.values[k], rd.stderrs[k]);
            rd.values[k] = g.ugr;
            rd.stderrs[k] = g.ugr_stderr;
            rd.glare.push_back(std::move(g));
        }
    }
}

}  // namespace sr
