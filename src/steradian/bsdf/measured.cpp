#include "steradian/bsdf/measured.h"

#include <array>
#include <cmath>

#include "steradian/bsdf/tensor_file.h"
#include "steradian/core/error.h"
#include "steradian/core/input_file.h"

namespace sr {

namespace {

/// Reads the fields of a .bsdf file, every error naming the file.
class BsdfFields {
  public:
    BsdfFields(const TensorFile& file, std::string_view name) : m_file(file), m_name(name) {}

    [[noreturn]] void fail(const std::string& why) const {
        throw Error(fmt::format("{}: {}", m_name, why));
    }
    /// The field, which must be float32 of `ndim` dimensions, each at least `min_extent`.
    const TensorField& floats(const char* field, size_t ndim, uint64_t min_extent = 1) const {
        const TensorField* f = m_file.find(field);
        if (!f) {
            if (std::string_view(field) == "spectra" && m_file.find("rgb"))
                fail(
                    "no \"spectra\" field (an RGB-only file): steradian, like pbrt-v4, reads "
                    "the spectral tables");
            fail(fmt::format("not a measured BRDF file: no field \"{}\"", field));
        }
        if (f->dtype != TensorDtype::Float32 || f->shape.size() != ndim)
            fail(fmt::format("field \"{}\" is {}, expected float32 of {} dimensions", field,
                             f->describe(), ndim));
        for (uint64_t s : f->shape)
            if (s < min_extent)
                fail(fmt::format("field \"{}\" is {}: every extent must be at least {}", field,
                                 f->describe(), min_extent));
        return *f;
    }
    /// The field's leading extents must be `lead` (the parameters' counts).
    void expect_lead(const char* field, const TensorField& f, std::initializer_list<uint64_t> lead,
                     const char* what) const {
        size_t i = 0;
        for (uint64_t n : lead)
            if (f.shape[i++] != n)
                fail(fmt::format("field \"{}\" is {}: its leading extents must be {}", field,
                                 f.describe(), what));
    }
    /// A table from a field's values; errors of its data name the field.
    PiecewiseLinear2D table(const char* field, const TensorField& f,
                            std::span<const std::vector<float>> params, bool sampling) const {
        std::vector<float> v = f.floats();
        size_t nd = f.shape.size();
        try {
            return PiecewiseLinear2D(v, int(f.shape[nd - 1]), int(f.shape[nd - 2]), params,
                                     sampling);
        } catch (const Error& e) {
            fail(fmt::format("field \"{}\": {}", field, e.what()));
        }
    }

  private:
    const TensorFile& m_file;
    std::string_view m_name;
};

/// An extent that the tables' int indices can hold (a file that large cannot be read anyway).
constexpr uint64_t kMaxExtent = uint64_t(1) << 24;

}  // namespace

MeasuredBrdf parse_measured_brdf(std::string_view bytes, std::string_view name) {
    TensorFile file = parse_tensor_file(bytes, name);
    BsdfFields in(file, name);
    const TensorField& theta_f = in.floats("theta_i", 1);
    const TensorField& phi_f = in.floats("phi_i", 1);
    const TensorField& lambda_f = in.floats("wavelengths", 1);
    const TensorField& ndf = in.floats("ndf", 2, 2);
    const TensorField& sigma = in.floats("sigma", 2, 2);
    const TensorField& vndf = in.floats("vndf", 4, 1);
    const TensorField& lum = in.floats("luminance", 4, 1);
    const TensorField& spectra = in.floats("spectra", 5, 1);
    for (const TensorField* f : {&ndf, &sigma, &vndf, &lum, &spectra})
        for (uint64_t s : f->shape)
            if (s > kMaxExtent)
                in.fail(fmt::format("a table of shape {}: extents above {} are not supported",
                                    f->describe(), kMaxExtent));

    const TensorField* jac = file.find("jacobian");
    if (!jac || jac->dtype != TensorDtype::UInt8 || jac->shape.size() != 1 || jac->shape[0] != 1)
        in.fail(fmt::format("field \"jacobian\" is {}, expected uint8 [1]",
                            jac ? jac->describe() : std::string("missing")));
    if (jac->bytes[0] != 1)
        in.fail(
            "\"jacobian\" is 0 (tables without the microfacet factor D / (4 sigma)): not "
            "supported; pbrt-v4 reads every file as if it were 1");

    uint64_t n_phi = phi_f.shape[0], n_theta = theta_f.shape[0], n_lambda = lambda_f.shape[0];
    std::vector<float> theta = theta_f.floats(), phi = phi_f.floats();
    for (float t : theta)
        if (!(t >= 0 && t <= kPiOver2 * 1.0001f))
            in.fail(fmt::format("field \"theta_i\": {} is not an angle in [0, pi/2] radians", t));
    MeasuredBrdf b;
    b.name = std::string(name);
    b.wavelengths = lambda_f.floats();
    b.isotropic = n_phi <= 2;
    if (!b.isotropic) {
        // pbrt-v4 renders only tables over the whole circle (its "reduction" of 1).
        float span = phi.back() - phi.front();
        if (!(std::abs(span - 2 * kPi) < 0.25f * kPi))
            in.fail(
                fmt::format("field \"phi_i\" spans {} radians: anisotropic tables over "
                            "less than the full circle (symmetry reductions) are not "
                            "supported (nor by pbrt-v4)",
                            span));
    }
    in.expect_lead("vndf", vndf, {n_phi, n_theta}, "(phi_i, theta_i)");
    in.expect_lead("luminance", lum, {n_phi, n_theta}, "(phi_i, theta_i)");
    in.expect_lead("spectra", spectra, {n_phi, n_theta, n_lambda}, "(phi_i, theta_i, wavelengths)");
    if (lum.shape[2] != spectra.shape[3] || lum.shape[3] != spectra.shape[4])
        in.fail(fmt::format("\"luminance\" is {} and \"spectra\" {}: their grids must agree",
                            lum.describe(), spectra.describe()));

    const std::vector<float> angles[2] = {phi, theta};
    const std::vector<float> spectral[3] = {phi, theta, b.wavelengths};
    b.ndf = in.table("ndf", ndf, {}, false);
    b.sigma = in.table("sigma", sigma, {}, false);
    b.vndf = in.table("vndf", vndf, angles, true);
    b.luminance = in.table("luminance", lum, angles, true);
    b.spectra = in.table("spectra", spectra, spectral, false);
    return b;
}

MeasuredBrdf read_measured_brdf(const std::string& path) {
    std::string bytes = read_regular_file(path, kMaxSceneFileBytes, "measured BRDF file");
    return parse_measured_brdf(bytes, path);
}

namespace {

/// Spherical angles of a unit vector of the upper hemisphere. theta by atan2, not acos(z):
/// near the pole acos of a float z is off by up to 3e-4 rad (z rounds to 1 within 2.4e-4 rad),
/// which moved half vectors near the mirror direction onto the table's pole, where the VNDF
/// density vanishes.
struct Angles {
    Float theta, phi;
};
Angles angles_of(Vec3 w) {
    return {std::atan2(std::sqrt(sqr(w.x) + sqr(w.y)), w.z), std::atan2(w.y, w.x)};
}

/// (u, v) of the half vector; of isotropic tables, v of phi_m - phi_o, wrapped into [0, 1).
Point2 half_vector_uv(const MeasuredBrdf& b, Vec3 wm, Float phi_o) {
    Angles m = angles_of(wm);
    Float v = measured_phi_to_v(b.isotropic ? m.phi - phi_o : m.phi);
    return {measured_theta_to_u(m.theta), v - std::floor(v)};
}

/// The tabulated factor D(wm) / (4 sigma(wo)) of f, 0 where the tables give none.
Float microfacet_factor(const MeasuredBrdf& b, Point2 uv_m, Angles o) {
    Float s = b.sigma.evaluate({measured_theta_to_u(o.theta), measured_phi_to_v(o.phi)});
    Float d = b.ndf.evaluate(uv_m);
    return s > 0 && d > 0 ? d / (4 * s) : 0;
}

/// max(0, fr) at u' times the factor k; 0 where the product is not finite (only absurd tables,
/// values near the float range, give that).
SampledSpectrum spectral_values(const MeasuredBrdf& b, Point2 u, Angles o,
                                const SampledWavelengths& lambda, Float k) {
    SampledSpectrum f;
    for (int i = 0; i < kSpectrumSamples; ++i) {
        const Float params[3] = {o.phi, o.theta, lambda.lambda[i]};
        f[i] = std::max(Float(0), b.spectra.evaluate(u, params)) * k;
    }
    return f.has_nonfinite() ? SampledSpectrum(0) : f;
}

/// The solid-angle Jacobian of wi over (u, v) of wm: 4 (wo . wm) 2 pi^2 u sin(theta_m),
/// bounded below as pbrt-v4 does (wm at the pole).
Float wi_jacobian(Float wo_dot_wm, Float u_m, Float sin_theta_m) {
    return 4 * wo_dot_wm * std::max(2 * kPi * kPi * u_m * sin_theta_m, Float(1e-6));
}

/// A reflection configuration mirrored to the upper side, with its half vector and that
/// vector's table coordinates; empty when wo and wi lie on opposite sides (or wi = -wo).
struct Reflection {
    Vec3 wo, wi, wm;
    Angles o;
    Point2 uv_m;
};
std::optional<Reflection> reflection(const MeasuredBrdf& b, Vec3 wo, Vec3 wi) {
    if (!(wo.z * wi.z > 0)) return std::nullopt;
    if (wo.z < 0) {
        wo = -wo;
        wi = -wi;
    }
    Vec3 h = wo + wi;
    if (length_squared(h) == 0) return std::nullopt;
    Reflection r{wo, wi, normalize(h), angles_of(wo), {}};
    r.uv_m = half_vector_uv(b, r.wm, r.o.phi);
    return r;
}

}  // namespace

SampledSpectrum MeasuredLobe::f(Vec3 wo, Vec3 wi, TransportMode) const {
    std::optional<Reflection> r = reflection(*brdf, wo, wi);
    if (!r) return SampledSpectrum(0);
    const Float params[2] = {r->o.phi, r->o.theta};
    Point2 u = brdf->vndf.invert(r->uv_m, params).p;
    Float k = microfacet_factor(*brdf, r->uv_m, r->o) / r->wi.z;
    if (!(k > 0) || !std::isfinite(k)) return SampledSpectrum(0);
    return spectral_values(*brdf, u, r->o, lambda, k);
}

std::optional<BsdfSample> MeasuredLobe::sample(Vec3 wo, Float, Point2 u, TransportMode) const {
    bool flip = wo.z < 0;
    if (flip) wo = -wo;
    Angles o = angles_of(wo);
    const Float params[2] = {o.phi, o.theta};
    PiecewiseLinear2D::Sample lum = brdf->luminance.sample(u, params);
    PiecewiseLinear2D::Sample m = brdf->vndf.sample(lum.p, params);
    Float theta_m = measured_u_to_theta(m.p.x);
    Float phi_m = measured_v_to_phi(m.p.y) + (brdf->isotropic ? o.phi : 0);
    Float sin_m = std::sin(theta_m);
    Vec3 wm(sin_m * std::cos(phi_m), sin_m * std::sin(phi_m), std::cos(theta_m));
    Float wo_dot_wm = dot(wo, wm);
    Vec3 wi = 2 * wo_dot_wm * wm - wo;
    if (!(wi.z > 0) || !(wo_dot_wm > 0)) return std::nullopt;
    Float k = microfacet_factor(*brdf, m.p, o) / wi.z;
    Float pdf = lum.pdf * m.pdf / wi_jacobian(wo_dot_wm, m.p.x, sin_m);
    if (!(pdf > 0) || !std::isfinite(pdf)) return std::nullopt;
    BsdfSample s;
    // A zero f (tables that give none here) is returned as such, so that sample() draws from
    // pdf(); the Bsdf drops it.
    s.f = k > 0 && std::isfinite(k) ? spectral_values(*brdf, lum.p, o, lambda, k)
                                    : SampledSpectrum(0);
    s.wi = flip ? -wi : wi;
    s.pdf_sa = pdf;
    s.flags = kLobeReflection | kLobeGlossy;
    return s;
}

Float MeasuredLobe::pdf(Vec3 wo, Vec3 wi, TransportMode) const {
    std::optional<Reflection> r = reflection(*brdf, wo, wi);
    if (!r) return 0;
    const Float params[2] = {r->o.phi, r->o.theta};
    PiecewiseLinear2D::Sample m = brdf->vndf.invert(r->uv_m, params);
    Float p_lum = brdf->luminance.evaluate(m.p, params);
    Float sin_m = std::sqrt(sqr(r->wm.x) + sqr(r->wm.y));
    Float pdf = m.pdf * p_lum / wi_jacobian(dot(r->wo, r->wm), r->uv_m.x, sin_m);
    return std::isfinite(pdf) && pdf > 0 ? pdf : 0;
}

}  // namespace sr
