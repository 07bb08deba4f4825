#pragma once
// Helpers for scene-level tests: render a pbrt-v4 scene given as text and summarise pixel
// statistics. Tolerances in the tests come from these estimated standard errors.
#include <cmath>
#include <string>
#include <vector>

#include "steradian/film/film.h"
#include "steradian/integrators/integrator.h"
#include "steradian/integrators/measure.h"
#include "steradian/scene/build.h"
#include "steradian/scene/pbrt/parser.h"

namespace sr::test {

struct Rendered {
    Image rgb;
    std::vector<double> y;  ///< luminance per pixel (film Y)
    RenderStats stats;
    int width = 0, height = 0;
};

/// Measures the meters of a built scene to the relative error `rel_error`.
inline MeasureResult measure_scene(const Scene& s, double rel_error, int threads = 2) {
    MeasureOptions o;
    o.rel_error = rel_error;
    o.threads = threads;
    return measure(s, o);
}

/// Measures the meters of a pbrt-v4 scene given as text (files named in it resolve against
/// base_dir).
inline MeasureResult measure_string(const std::string& pbrt, double rel_error,
                                    const std::string& base_dir = ".", int threads = 2) {
    return measure_scene(build_scene(parse_pbrt_string(pbrt, "<test>", base_dir), {}), rel_error,
                         threads);
}

/// Renders a pbrt-v4 scene given as text; `ro` gives the options other than threads and spp
/// (the seed, for instance).
inline Rendered render_string(const std::string& pbrt, int threads = 2, int spp = 0,
                              const std::string& base_dir = ".", RenderOptions ro = {}) {
    SceneDesc d = parse_pbrt_string(pbrt, "<test>", base_dir);
    BuildOptions bo;
    bo.spp_override = spp;
    Scene s = build_scene(d, bo);
    Film film(s.film);
    ro.threads = threads;
    ro.spp = spp;
    Rendered r;
    r.stats = render(s, film, ro);
    r.rgb = film.rgb_image();
    r.y = film.luminance();
    r.width = s.film.width();
    r.height = s.film.height();
    return r;
}

/// A white furnace: a unit sphere (with `world`'s material lines) seen by a 16 x 16 camera
/// under a uniform environment of radiance 1; the sphere covers the pixels [4, 12)^2.
inline std::string furnace_scene(const std::string& world, int spp, int max_depth) {
    return R"(
LookAt 0 0 -4  0 0 0  0 1 0
Camera "perspective" "float fov" [ 30 ]
Film "rgb" "integer xresolution" [ 16 ] "integer yresolution" [ 16 ] "string filename" "x.exr"
Sampler "independent" "integer pixelsamples" [ )" +
           std::to_string(spp) + R"( ]
Integrator "path" "integer maxdepth" [ )" +
           std::to_string(max_depth) + R"( ]
PixelFilter "box"
WorldBegin
LightSource "infinite" "spectrum L" [ 300 1 900 1 ]
)" + world + R"(
Shape "sphere" "float radius" [ 1 ]
)";
}

/// The square [-1, 1]^2 in z = 0 with uv (0,0)..(1,1) (u along raster x, v up), filling a 16 x
/// 16 orthographic view and lit head-on by a distant light of pi lux, so that a Lambertian
/// surface's radiance is its reflectance; `world` gives its textures and material.
inline std::string lit_plane_scene(const std::string& world, int spp) {
    return R"(
Scale -1 1 1
LookAt 0 0 5  0 0 0  0 1 0
Camera "orthographic" "float screenwindow" [ -1 1 -1 1 ]
Film "rgb" "integer xresolution" [ 16 ] "integer yresolution" [ 16 ] "string filename" "x.exr"
Sampler "zsobol" "integer pixelsamples" [ )" +
           std::to_string(spp) + R"( ]
Integrator "path" "integer maxdepth" [ 1 ]
PixelFilter "box"
WorldBegin
LightSource "distant" "point3 from" [ 0 0 1 ] "point3 to" [ 0 0 0 ] "float illuminance" [ 3.14159265358979 ]
)" + world + R"(
Shape "bilinearmesh" "point3 P" [ -1 -1 0  1 -1 0  -1 1 0  1 1 0 ]
    "point2 uv" [ 0 0  1 0  0 1  1 1 ]
)";
}

/// Mean and standard error of the mean over a set of (independent) pixel values.
struct MeanSe {
    double mean = 0, se = 0;
    size_t n = 0;
};

inline MeanSe mean_se(const std::vector<double>& v) {
    MeanSe m;
    m.n = v.size();
    if (v.empty()) return m;
    double s = 0, s2 = 0;
    for (double x : v) s += x, s2 += x * x;
    m.mean = s / double(v.size());
    double var = std::max(0.0, s2 / double(v.size()) - m.mean * m.mean) * double(v.size()) /
                 std::max<double>(1, double(v.size()) - 1);
    m.se = std::sqrt(var / double(v.size()));
    return m;
}

/// Values of channel c (0..2 RGB, 3 = luminance Y) inside the rectangle [x0,x1) x [y0,y1).
inline std::vector<double> region(const Rendered& r, int x0, int y0, int x1, int y1, int c = 3) {
    std::vector<double> v;
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x)
            v.push_back(c == 3 ? r.y[size_t(y) * r.width + x] : r.rgb.at(x, y, c));
    return v;
}

}  // namespace sr::test
