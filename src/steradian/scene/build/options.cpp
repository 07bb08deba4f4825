/// The options block: colour space, film, camera, pixel filter, sampler and integrator.
#include <fmt/ranges.h>

#include <map>

#include "steradian/film/sensor.h"
#include "steradian/scene/build/builder.h"
#include "steradian/spectrum/camera_sensors.h"

namespace sr::build_detail {

void Builder::build_options_block() {
    for (const EntityDesc& cs : m_d.color_spaces)
        recorded([&] {
            if (cs.type != "srgb")
                throw_unsupported(cs.loc, "ColorSpace \"{}\" is not supported yet (only \"srgb\")",
                                  cs.type);
        });
    if (!m_d.accelerator.type.empty())
        warning(m_d.accelerator.loc,
                fmt::format("Accelerator \"{}\" ignored: steradian always uses Embree",
                            m_d.accelerator.type));
    for (const Param& p : m_d.options.params())
        if (p.name != "seed") warning(p.loc, fmt::format("Option \"{}\" is ignored", p.name));
    // What is unsupported in one of them is recorded, and pbrt-v4's default stands in.
    auto or_default = [&](const auto& desc, auto make) {
        if (recorded([&] { (this->*make)(desc); })) return;
        auto d = desc;
        d.type.clear();
        d.params = ParamSet();
        (this->*make)(d);
    };
    or_default(m_d.film, &Builder::build_film);
    or_default(m_d.camera, &Builder::build_camera);
    or_default(m_d.filter, &Builder::build_filter);
    or_default(m_d.sampler, &Builder::build_sampler);
    or_default(m_d.integrator, &Builder::build_integrator);
}

void Builder::build_film(const EntityDesc& f) {
    FilmParams fp;
    const std::string type = f.type.empty() ? "rgb" : f.type;
    if (type == "gbuffer")
        fp.kind = FilmKind::GBuffer;
    else if (type == "spectral")
        fp.kind = FilmKind::Spectral;
    else if (type != "rgb")
        unsupported(f, "Film");
    const ParamSet& ps = f.params;
    fp.resolution = Vec2i(ps.get_int("xresolution", 1280), ps.get_int("yresolution", 720));
    if (fp.resolution.x <= 0 || fp.resolution.y <= 0)
        throw_error(f.loc, "film resolution must be positive");
    if (fp.resolution.x > kMaxFilmSide || fp.resolution.y > kMaxFilmSide ||
        int64_t(fp.resolution.x) * fp.resolution.y > kMaxFilmPixels)
        throw_error(f.loc,
                    "film resolution {} x {} is too large: at most {} pixels a side and {} "
                    "pixels in all",
                    fp.resolution.x, fp.resolution.y, kMaxFilmSide, kMaxFilmPixels);
    fp.filename = ps.get_string("filename", "pbrt.exr");
    if (fp.kind != FilmKind::Rgb &&
        !(fp.filename.size() >= 4 && fp.filename.compare(fp.filename.size() - 4, 4, ".exr") == 0)) {
        const Param* p = ps.find("filename");
        throw_error(p ? p->loc : f.loc,
                    "Film \"{}\": \"{}\": EXR is the only output format of this film (as in "
                    "pbrt-v4): its channels are more than RGB",
                    type, fp.filename);
    }
    fp.x0 = 0;
    fp.x1 = fp.resolution.x;
    fp.y0 = 0;
    fp.y1 = fp.resolution.y;
    if (auto pb = ps.get_ints("pixelbounds"); !pb.empty()) {
        if (pb.size() != 4) throw_error(f.loc, "\"pixelbounds\" needs 4 values");
        fp.x0 = clamp(pb[0], 0, fp.resolution.x);
        fp.x1 = clamp(pb[1], 0, fp.resolution.x);
        fp.y0 = clamp(pb[2], 0, fp.resolution.y);
        fp.y1 = clamp(pb[3], 0, fp.resolution.y);
    }
    if (auto cw = ps.get_floats("cropwindow"); !cw.empty()) {
        if (cw.size() != 4) throw_error(f.loc, "\"cropwindow\" needs 4 values");
        Float x0 = clamp(std::min(cw[0], cw[1]), Float(0), Float(1));
        Float x1 = clamp(std::max(cw[0], cw[1]), Float(0), Float(1));
        Float y0 = clamp(std::min(cw[2], cw[3]), Float(0), Float(1));
        Float y1 = clamp(std::max(cw[2], cw[3]), Float(0), Float(1));
        fp.x0 = int(std::ceil(fp.resolution.x * x0));
        fp.x1 = int(std::ceil(fp.resolution.x * x1));
        fp.y0 = int(std::ceil(fp.resolution.y * y0));
        fp.y1 = int(std::ceil(fp.resolution.y * y1));
    }
    if (fp.x1 <= fp.x0 || fp.y1 <= fp.y0)
        throw_error(f.loc, "the crop window / pixel bounds select no pixels");
    Float iso = ps.get_float("iso", 100);
    m_exposure_iso = iso / 100;
    // pbrt-v3's film "scale": pbrt-v4 reports it as an unused parameter, and its --upgrade
    // rewrites it as "iso" 100 x scale. We read it as that upgrade would, with a warning.
    if (const Param* sc = ps.find("scale")) {
        const Float scale = ps.get_float("scale", 1);
        warning(sc->loc, fmt::format("Film \"{}\": \"scale\" is pbrt-v3's (pbrt-v4 rejects "
                                     "it); read as pbrt-v4's --upgrade does, as \"iso\" x {}",
                                     f.type.empty() ? "rgb" : f.type, scale));
        m_exposure_iso *= scale;
    }
    // pbrt-v4's PixelSensor::Create: a camera sensor is white balanced for daylight of
    // 6500 K unless told otherwise ("whitebalance" 0 too), the CIE sensor only when asked.
    const std::string sensor = ps.get_string("sensor", "cie1931");
    Float wb = ps.get_float("whitebalance", 0);
    if (wb < 0) throw_error(f.loc, "\"whitebalance\" must be >= 0 (kelvin; 0: none)");
    if (sensor == "cie1931") {
        if (wb > 0) {
            // White balance from the CIE daylight illuminant of that temperature.
            Xyz w = spectrum_to_xyz(cie_d_illuminant(wb));
            Float sum = w.x + w.y + w.z;
            fp.rgb_from_sensor = srgb_from_xyz_white_balanced(w.x / sum, w.y / sum);
        } else {
            fp.rgb_from_sensor = srgb_from_xyz_matrix();
        }
    } else {
        const auto curves = camera_sensor_curves(sensor);
        if (!curves) {
            const Param* p = ps.find("sensor");
            throw_error(p ? p->loc : f.loc, "unknown sensor \"{}\": expected cie1931, {}", sensor,
                        fmt::join(camera_sensor_names(), ", "));
        }
        if (wb == 0) wb = 6500;
        fp.sensor_rgb = std::array<Spectrum, 3>{(*curves)[0], (*curves)[1], (*curves)[2]};
        const Matrix3 xyz_from_sensor =
            fit_xyz_from_sensor_rgb(*fp.sensor_rgb, cie_d_illuminant(wb), srgb_illuminant());
        fp.rgb_from_sensor = multiply(srgb_from_xyz_matrix(), xyz_from_sensor);
        fp.luminance_from_sensor = xyz_from_sensor[1];
    }
    if (fp.kind == FilmKind::GBuffer) {
        const std::string cs = ps.get_string("coordinatesystem", "camera");
        if (cs != "camera" && cs != "world")
            throw_error(ps.find("coordinatesystem")->loc,
                        "unknown \"coordinatesystem\" \"{}\": expected camera or world", cs);
        fp.gbuffer_camera_space = cs == "camera";
    }
    if (fp.kind == FilmKind::Spectral) {
        fp.buckets = ps.get_int("nbuckets", 16);
        fp.lambda_min = ps.get_float("lambdamin", kLambdaMin);
        fp.lambda_max = ps.get_float("lambdamax", kLambdaMax);
        if (!(fp.lambda_min >= kLambdaMin && fp.lambda_max <= kLambdaMax &&
              fp.lambda_min < fp.lambda_max))
            throw_error(f.loc,
                        "\"lambdamin\" {} and \"lambdamax\" {}: expected {} <= lambdamin < "
                        "lambdamax <= {} nm (the wavelengths steradian renders)",
                        fp.lambda_min, fp.lambda_max, kLambdaMin, kLambdaMax);
        // Two sums a bucket and pixel, in double: at most 2^28 of them (2 GiB).
        const int64_t pixels = int64_t(fp.width()) * fp.height();
        if (fp.buckets < 1 || int64_t(fp.buckets) * 2 * pixels > (int64_t(1) << 28))
            throw_error(ps.find("nbuckets") ? ps.find("nbuckets")->loc : f.loc,
                        "\"nbuckets\" {}: expected 1 or more, and at most {} for {} pixels",
                        fp.buckets, (int64_t(1) << 27) / pixels, pixels);
    }
    fp.max_component = ps.get_float("maxcomponentvalue", kInfinity);
    fp.half_float = ps.get_bool("savefp16", false);
    ps.get_float("diagonal", 35);  // only meaningful for the realistic camera
    ps.check_unused(fmt::format("Film \"{}\"", type));
    m_s.film = fp;
}

void Builder::build_camera(const CameraDesc& c) {
    std::string type = c.type.empty() ? "perspective" : c.type;
    const ParamSet& ps = c.params;
    CameraParams cp;
    cp.world_from_camera = c.world_from_camera;
    check_transform(c.world_from_camera, c.loc, "the camera");
    check_position(c.world_from_camera.point(Point3(0, 0, 0)), c.loc, "the camera");
    cp.resolution = m_s.film.resolution;
    Float shutter_open = ps.get_float("shutteropen", 0);
    Float shutter_close = ps.get_float("shutterclose", 1);
    if (shutter_close < shutter_open) throw_error(c.loc, "shutterclose is before shutteropen");
    m_s.film.imaging_ratio = (shutter_close - shutter_open) * m_exposure_iso;
    m_s.film.camera_from_world = c.world_from_camera.inverse();
    Float frame = ps.get_float("frameaspectratio", Float(cp.resolution.x) / Float(cp.resolution.y));
    if (frame > 1) {
        cp.screen[0] = -frame;
        cp.screen[1] = frame;
        cp.screen[2] = -1;
        cp.screen[3] = 1;
    } else {
        cp.screen[0] = -1;
        cp.screen[1] = 1;
        cp.screen[2] = -1 / frame;
        cp.screen[3] = 1 / frame;
    }
    if (auto sw = ps.get_floats("screenwindow"); !sw.empty()) {
        if (sw.size() != 4) throw_error(c.loc, "\"screenwindow\" needs 4 values");
        for (int i = 0; i < 4; ++i) cp.screen[i] = sw[i];
    }
    cp.lens_radius = ps.get_float("lensradius", 0);
    cp.focal_distance = ps.get_float("focaldistance", 1e6f);
    if (type == "perspective") {
        Float fov = ps.get_float("fov", 90);
        if (!(fov > 0 && fov < 180)) throw_error(c.loc, "fov must be in (0, 180) degrees");
        ps.check_unused("Camera \"perspective\"");
        m_s.camera = std::make_unique<PerspectiveCamera>(cp, fov);
    } else if (type == "orthographic") {
        ps.check_unused("Camera \"orthographic\"");
        m_s.camera = std::make_unique<OrthographicCamera>(cp);
    } else {
        CameraDesc cc = c;
        cc.type = type;
        unsupported(cc, "Camera");
    }
    if (m_s.camera) m_s.camera->find_min_differentials(cp.resolution);
}

void Builder::build_filter(const EntityDesc& f) {
    std::string type = f.type.empty() ? "gaussian" : f.type;
    const ParamSet& ps = f.params;
    FilterType t;
    Float def_r;
    if (type == "box")
        t = FilterType::Box, def_r = 0.5f;
    else if (type == "triangle")
        t = FilterType::Triangle, def_r = 2;
    else if (type == "gaussian")
        t = FilterType::Gaussian, def_r = 1.5f;
    else {
        EntityDesc e = f;
        e.type = type;
        unsupported(e, "PixelFilter");
    }
    Vec2 r(ps.get_float("xradius", def_r), ps.get_float("yradius", def_r));
    if (!(r.x > 0 && r.y > 0)) throw_error(f.loc, "filter radius must be positive");
    Float sigma = t == FilterType::Gaussian ? ps.get_float("sigma", 0.5f) : 0.5f;
    ps.check_unused(fmt::format("PixelFilter \"{}\"", type));
    m_s.filter = std::make_unique<Filter>(t, r, sigma);
}

void Builder::build_sampler(const EntityDesc& s) {
    std::string type = s.type.empty() ? "zsobol" : s.type;
    const ParamSet& ps = s.params;
    SamplerSettings ss;
    static const std::map<std::string, std::string> names = {
        {"independent", "independent"}, {"stratified", "stratified"},
        {"zsobol", "zsobol"},           {"sobol", "sobol"},
        {"paddedsobol", "paddedsobol"}, {"halton", "zsobol"},
        {"pmj02bn", "paddedsobol"}};
    auto it = names.find(type);
    if (it == names.end()) {
        EntityDesc e = s;
        e.type = type;
        unsupported(e, "Sampler");
    }
    if (it->first != it->second && type != "sobol")
        warning(s.loc, fmt::format("Sampler \"{}\" is rendered with our \"{}\" sampler", type,
                                   it->second));
    ss.type = it->second;
    int option_seed = 0;
    if (const Param* p = m_d.options.find("seed"))
        option_seed = p->numbers.empty() ? 0 : int(p->numbers[0]);
    ss.seed = uint64_t(ps.get_int("seed", option_seed));
    if (type == "stratified") {
        ss.x_samples = ps.get_int("xsamples", 4);
        ss.y_samples = ps.get_int("ysamples", 4);
        ss.jitter = ps.get_bool("jitter", true);
        if (ss.x_samples <= 0 || ss.y_samples <= 0)
            throw_error(s.loc, "xsamples and ysamples must be positive");
        // Checked in 64 bits: 65536 x 65536 overflowed int and rendered a black image.
        if (int64_t(ss.x_samples) * ss.y_samples > kMaxSamplesPerPixel)
            throw_error(s.loc, "xsamples x ysamples = {} x {} is more than {} samples per pixel",
                        ss.x_samples, ss.y_samples, kMaxSamplesPerPixel);
        ss.spp = ss.x_samples * ss.y_samples;
    } else {
        ss.spp = ps.get_int("pixelsamples", 16);
        if (ss.spp <= 0) throw_error(s.loc, "pixelsamples must be positive");
        if (ss.spp > kMaxSamplesPerPixel)
            throw_error(s.loc, "pixelsamples {} is more than {}", ss.spp, kMaxSamplesPerPixel);
        ps.get_string("randomization", "");
    }
    if (m_o.spp_override > 0) ss.spp = m_o.spp_override;
    ps.check_unused(fmt::format("Sampler \"{}\"", type));
    m_s.sampler = ss;
}

void Builder::build_integrator(const EntityDesc& e) {
    std::string type = e.type.empty() ? "volpath" : e.type;
    const ParamSet& ps = e.params;
    IntegratorSettings is;
    if (type == "path" || type == "volpath") {
        m_volpath = type == "volpath";
        is.max_depth = ps.get_int("maxdepth", 5);
        is.regularize = ps.get_bool("regularize", false);
        std::string strategy = ps.get_string("strategy", "mis");
        if (strategy == "mis")
            is.strategy = LightStrategy::Mis;
        else if (strategy == "bsdf")
            is.strategy = LightStrategy::BsdfOnly;
        else if (strategy == "light")
            is.strategy = LightStrategy::LightOnly;
        else
            throw_error(e.loc, "unknown \"strategy\" \"{}\": expected mis, bsdf or light",
                        strategy);
    } else if (type == "radiosity") {
        // A steradian extension (docs/radiosity.md).
        RadiosityParams& r = is.radiosity;
        r.max_depth = is.max_depth = ps.get_int("maxdepth", 5);
        r.patch_size = ps.get_float("patchsize", 0);
        r.max_patches = ps.get_int("maxpatches", r.max_patches);
        r.subdivide = ps.get_float("subdivide", r.subdivide);
        r.residual = ps.get_float("residual", r.residual);
        r.direct_samples = ps.get_int("directsamples", r.direct_samples);
        r.interpolate = ps.get_bool("interpolate", r.interpolate);
        const std::string solver = ps.get_string("solver", "hierarchical");
        if (solver == "hierarchical")
            r.hierarchical = true;
        else if (solver == "matrix")
            r.hierarchical = false;
        else
            throw_error(e.loc, "unknown \"solver\" \"{}\": expected hierarchical or matrix",
                        solver);
        r.link_error = ps.get_float("linkerror", r.link_error);
        r.gather_distance = ps.get_float("gatherdistance", r.gather_distance);
        if (!(r.gather_distance >= 0) || !std::isfinite(r.gather_distance))
            throw_error(e.loc, "\"gatherdistance\" must be >= 0 (0: no secondary gather)");
        if (!(r.link_error > 0 && r.link_error < 1))
            throw_error(e.loc, "\"linkerror\" must be in (0, 1)");
        if (!(r.patch_size >= 0) || !std::isfinite(r.patch_size))
            throw_error(e.loc, "\"patchsize\" must be >= 0 (0: from \"maxpatches\")");
        if (!r.hierarchical && (r.max_patches < 1 || r.max_patches > 20000))
            throw_error(e.loc, "\"maxpatches\" {} is outside 1..20000 (the \"matrix\" "
                        "solver's form factors are a dense matrix of maxpatches^2 floats)",
                        r.max_patches);
        if (r.hierarchical && (r.max_patches < 1 || r.max_patches > 1000000))
            throw_error(e.loc, "\"maxpatches\" {} is outside 1..1000000", r.max_patches);
        if (!(r.subdivide >= 0) || !std::isfinite(r.subdivide))
            throw_error(e.loc, "\"subdivide\" must be >= 0 (0: no adaptive subdivision)");
        if (!(r.residual > 0 && r.residual < 1))
            throw_error(e.loc, "\"residual\" must be in (0, 1)");
        if (r.direct_samples < 1 || r.direct_samples > 4096)
            throw_error(e.loc, "\"directsamples\" must be in 1..4096");
    } else if (type == "bdpt" || type == "lightpath") {
        // pbrt-v4's BDPTIntegrator::Create and LightPathIntegrator::Create (both with the
        // power light sampler, and no "lightsampler" parameter).
        is.max_depth = ps.get_int("maxdepth", 5);
        if (type == "bdpt") {
            is.visualize_strategies = ps.get_bool("visualizestrategies", false);
            is.visualize_weights = ps.get_bool("visualizeweights", false);
            is.regularize = ps.get_bool("regularize", false);
            if ((is.visualize_strategies || is.visualize_weights) && is.max_depth > 5) {
                warning(e.loc, "Integrator \"bdpt\": visualizestrategies/visualizeweights was "
                               "enabled, limiting maxdepth to 5 (as pbrt-v4)");
                is.max_depth = 5;
            }
        }
        if (is.max_depth < 0) throw_error(e.loc, "maxdepth must be >= 0");
        ps.check_unused(fmt::format("Integrator \"{}\"", type));
        is.type = type;
        is.light_sampler = "power";
        m_s.integrator = is;
        return;
    } else if (type == "mlt") {
        // pbrt-v4's MLTIntegrator::Create (the power light sampler; --spp overrides
        // "mutationsperpixel", as pbrt-v4's --spp does).
        is.max_depth = ps.get_int("maxdepth", 5);
        is.regularize = ps.get_bool("regularize", false);
        auto& m = is.mlt;
        m.bootstrap_samples = ps.get_int("bootstrapsamples", m.bootstrap_samples);
        m.chains = ps.get_int("chains", m.chains);
        m.mutations_per_pixel = ps.get_int("mutationsperpixel", m.mutations_per_pixel);
        m.large_step_probability = ps.get_float("largestepprobability", m.large_step_probability);
        m.sigma = ps.get_float("sigma", m.sigma);
        auto at = [&](const char* name) {
            const Param* p = ps.find(name);
            return p ? p->loc : e.loc;
        };
        if (is.max_depth < 0) throw_error(at("maxdepth"), "maxdepth must be >= 0");
        if (m.bootstrap_samples < 1)
            throw_error(at("bootstrapsamples"), "\"bootstrapsamples\" must be >= 1");
        if (m.chains < 1) throw_error(at("chains"), "\"chains\" must be >= 1");
        if (m.mutations_per_pixel < 1 || m.mutations_per_pixel > kMaxSamplesPerPixel)
            throw_error(at("mutationsperpixel"), "\"mutationsperpixel\" must be in 1..{}",
                        kMaxSamplesPerPixel);
        if (!(m.large_step_probability >= 0 && m.large_step_probability <= 1))
            throw_error(at("largestepprobability"),
                        "\"largestepprobability\" must be in [0, 1]");
        if (!(m.sigma > 0) || !std::isfinite(m.sigma))
            throw_error(at("sigma"), "\"sigma\" must be a positive finite number");
        ps.check_unused("Integrator \"mlt\"");
        is.type = type;
        is.light_sampler = "power";
        m_s.integrator = is;
        return;
    } else if (type == "sppm") {
        // pbrt-v4's SPPMIntegrator::Create: its iterations are the Sampler's pixel samples;
        // direct light with the "bvh" light sampler, photons from the "power" one.
        for (const char* old : {"iterations", "numiterations"})
            if (const Param* p = ps.find(old))
                throw_error(p->loc, "Integrator \"sppm\": \"{}\" is pbrt-v3's; in pbrt-v4 the "
                                    "iterations are the Sampler's \"pixelsamples\"",
                            old);
        is.max_depth = ps.get_int("maxdepth", 5);
        SppmParams& sp = is.sppm;
        sp.photons_per_iteration = ps.get_int("photonsperiteration", -1);
        sp.radius = ps.get_float("radius", 1);
        sp.seed = ps.get_int("seed", 0);
        if (is.max_depth < 0) throw_error(e.loc, "maxdepth must be >= 0");
        if (!(sp.radius > 0) || !std::isfinite(sp.radius) || sp.radius > 1e17f) {
            const Param* p = ps.find("radius");
            throw_error(p ? p->loc : e.loc,
                        "Integrator \"sppm\": \"radius\" must be a finite number > 0 (the "
                        "initial search radius, in world units)");
        }
        ps.check_unused(fmt::format("Integrator \"{}\"", type));
        is.type = type;
        is.light_sampler = "bvh";
        m_s.integrator = is;
        return;
    } else if (type == "vcm") {
        // A steradian extension (docs/vcm.md): vertex connection and merging, with the power
        // light sampler (light paths and light samples choose lights alike).
        is.max_depth = ps.get_int("maxdepth", 5);
        VcmParams& v = is.vcm;
        v.radius = ps.get_float("radius", 0);
        v.alpha = ps.get_float("radiusalpha", v.alpha);
        v.light_paths = ps.get_int("lightpathsperiteration", -1);
        v.seed = ps.get_int("seed", 0);
        v.connect = ps.get_bool("vertexconnection", true);
        v.merge = ps.get_bool("vertexmerging", true);
        auto at = [&](const char* name) {
            const Param* p = ps.find(name);
            return p ? p->loc : e.loc;
        };
        if (is.max_depth < 0) throw_error(at("maxdepth"), "maxdepth must be >= 0");
        if (is.max_depth > 250)
            throw_error(at("maxdepth"), "Integrator \"vcm\": \"maxdepth\" must be at most 250");
        if (!(v.radius >= 0) || !std::isfinite(v.radius) || v.radius > 1e17f)
            throw_error(at("radius"),
                        "Integrator \"vcm\": \"radius\" must be a finite number >= 0 (the "
                        "initial merge radius in world units; 0: 0.003 times the scene's "
                        "bounding-sphere radius)");
        if (!(v.alpha > 0 && v.alpha <= 1))
            throw_error(at("radiusalpha"),
                        "Integrator \"vcm\": \"radiusalpha\" must be in (0, 1] (the radius "
                        "of iteration i is radius * i^((radiusalpha - 1) / 2))");
        if (!v.connect && !v.merge)
            throw_error(at("vertexmerging"), "Integrator \"vcm\": \"vertexconnection\" and "
                                             "\"vertexmerging\" cannot both be false");
        ps.check_unused("Integrator \"vcm\"");
        is.type = type;
        is.light_sampler = "power";
        m_s.integrator = is;
        return;
    } else if (type == "simplepath") {
        is.max_depth = ps.get_int("maxdepth", 5);
        bool lights = ps.get_bool("samplelights", true);
        bool bsdf = ps.get_bool("samplebsdf", true);
        if (!bsdf) throw_error(e.loc, "\"samplebsdf\" false (uniform sampling) is not supported");
        is.strategy = lights ? LightStrategy::LightOnly : LightStrategy::BsdfOnly;
    } else {
        EntityDesc ee = e;
        ee.type = type;
        unsupported(ee, "Integrator");
    }
    if (const Param* rr = ps.find("rrthreshold")) {
        // pbrt-v3's Russian-roulette threshold: pbrt-v4 has none (its --upgrade removes it;
        // its roulette is fixed). Dropped with a warning, as the upgrade does.
        ps.get_float("rrthreshold", 1);
        warning(rr->loc, fmt::format("Integrator \"{}\": \"rrthreshold\" is pbrt-v3's (pbrt-v4 "
                                     "has no such parameter; its --upgrade drops it); ignored",
                                     type));
    }
    if (is.max_depth < 0) throw_error(e.loc, "maxdepth must be >= 0");
    std::string ls = ps.get_string("lightsampler", "bvh");
    if (ls == "uniform")
        is.light_sampler = "uniform";
    else if (ls == "power" || ls == "bvh")
        is.light_sampler = ls;
    else
        throw_error(e.loc, "unknown light sampler \"{}\"", ls);
    ps.check_unused(fmt::format("Integrator \"{}\"", type));
    is.type = type == "radiosity" ? "radiosity" : "path";
    m_s.integrator = is;
}

}  // namespace sr::build_detail
