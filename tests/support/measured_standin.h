#pragma once
// A stand-in for the RGL database's .bsdf files (which cannot be downloaded here): the tables
// of bsdf/measured.h computed in closed form from an analytic BRDF, a rough conductor with
// the Trowbridge-Reitz (GGX) distribution, Smith's height-correlated masking-shadowing and
// Schlick's Fresnel term with a normal-incidence reflectance F0 tabulated per wavelength:
//
//   f(wo, wi) = F(lambda, wo . wm) D(wm) G2(wo, wi) / (4 cos theta_o cos theta_i).
//
// Tables (Dupuy and Jakob 2018, in bsdf/measured.h's parameterisation):
// - ndf: D(wm); sigma: the projected microfacet area sigma(wo) = integral of D(m) <wo . m>
//   dm = cos theta_o (1 + Lambda(wo)) = (cos theta_o + sqrt(cos^2 theta_o + alpha^2 sin^2
//   theta_o)) / 2 (Heitz 2014, Eq. 2 and 86);
// - vndf: <wo . wm> D(wm) times the Jacobian 2 pi^2 u sin theta_m of the (u, v) square (the
//   visible normal density D_wo(wm) = <wo . wm> D(wm) / sigma(wo) up to the normalisation the
//   reader applies);
// - spectra: at each grid point u' the value fr with f = fr D / (4 sigma cos theta_i), i.e.
//   fr = F G2(wo, wi) sigma(wo) / cos theta_o = F G2 / G1(wo), at the wm that the tabulated
//   VNDF's own warp maps u' to (0 where wi falls below the surface);
// - luminance: the mean of spectra over the wavelengths. Then f cos theta_i / pdf =
//   fr / p_lum: sampling follows f cos up to fr's variation over the wavelengths.
// Resolutions are parameters, so tests can watch the interpolation error fall as they grow.
#include <cmath>
#include <string>
#include <vector>

#include "steradian/bsdf/measured.h"
#include "steradian/bsdf/microfacet.h"
#include "steradian/bsdf/tensor_file.h"
#include "steradian/sampling/piecewise_linear_2d.h"

namespace sr::test {

struct StandinSpec {
    Float alpha_x = 0.3f, alpha_y = 0.3f;
    bool anisotropic = false;  ///< tabulate phi_i over the circle (else one phi_i = 0)
    int ndf_res = 64;          ///< ndf and sigma: ndf_res x ndf_res
    int vndf_res = 32;         ///< vndf: vndf_res x vndf_res per (phi_i, theta_i)
    int spectra_res = 32;      ///< spectra and luminance grids
    int n_theta_i = 10;        ///< theta_i uniform over [0, theta_max_deg]
    Float theta_max_deg = 85;
    int n_phi_i = 9;  ///< anisotropic only: phi_i uniform over [-pi, pi]
    std::vector<float> wavelengths = {400, 500, 600, 700};
    std::vector<float> f0 = {0.9f, 0.5f, 0.7f, 0.3f};  ///< Schlick F0 per wavelength
};

inline Vec3 standin_direction(Float theta, Float phi) {
    return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

/// F0 at lambda: linear between the spec's wavelengths, the nearest end outside them.
inline Float standin_f0(const StandinSpec& s, Float lambda) {
    const auto& w = s.wavelengths;
    if (lambda <= w.front()) return s.f0.front();
    if (lambda >= w.back()) return s.f0.back();
    size_t i = 1;
    while (w[i] < lambda) ++i;
    Float t = (lambda - w[i - 1]) / (w[i] - w[i - 1]);
    return (1 - t) * s.f0[i - 1] + t * s.f0[i];
}

inline Float standin_fresnel(Float f0, Float cos_h) {
    Float m = 1 - std::max(Float(0), cos_h);
    return f0 + (1 - f0) * m * m * m * m * m;
}

/// The analytic BRDF the stand-in tabulates (upper hemisphere; 0 elsewhere).
inline Float standin_f(const StandinSpec& s, Vec3 wo, Vec3 wi, Float lambda) {
    if (wo.z <= 0 || wi.z <= 0) return 0;
    TrowbridgeReitz mf{s.alpha_x, s.alpha_y};
    Vec3 wm = normalize(wo + wi);
    return standin_fresnel(standin_f0(s, lambda), dot(wo, wm)) * mf.D(wm) * mf.G(wo, wi) /
           (4 * wo.z * wi.z);
}

/// sigma(wo) in closed form.
inline Float standin_sigma(const StandinSpec& s, Vec3 wo) {
    Float a2 = sqr(s.alpha_x * wo.x) + sqr(s.alpha_y * wo.y);  // alpha(phi)^2 sin^2 theta
    return Float(0.5) * (wo.z + std::sqrt(sqr(wo.z) + a2));
}

inline TensorFile standin_tensor(const StandinSpec& s) {
    TrowbridgeReitz mf{s.alpha_x, s.alpha_y};
    const int nl = int(s.wavelengths.size());
    std::vector<float> theta_i, phi_i;
    for (int k = 0; k < s.n_theta_i; ++k)
        theta_i.push_back(radians(s.theta_max_deg) * Float(k) / Float(s.n_theta_i - 1));
    if (s.anisotropic)
        for (int k = 0; k < s.n_phi_i; ++k)
            phi_i.push_back(-kPi + 2 * kPi * Float(k) / Float(s.n_phi_i - 1));
    else
        phi_i.push_back(0);
    auto grid = [](int i, int n) { return Float(i) / Float(n - 1); };
    auto dir_of = [](Float u, Float v, Float phi0) {
        return standin_direction(measured_u_to_theta(u), measured_v_to_phi(v) + phi0);
    };

    std::vector<float> ndf, sigma;
    for (int y = 0; y < s.ndf_res; ++y)
        for (int x = 0; x < s.ndf_res; ++x) {
            Vec3 w = dir_of(grid(x, s.ndf_res), grid(y, s.ndf_res), 0);
            ndf.push_back(mf.D(w));
            sigma.push_back(standin_sigma(s, w));
        }

    std::vector<float> vndf, spectra, luminance;
    for (float po : phi_i)
        for (float to : theta_i) {
            Vec3 wo = standin_direction(to, po);
            Float rel = s.anisotropic ? 0 : po;  // isotropic: v is phi_m - phi_o
            std::vector<float> slice;
            for (int y = 0; y < s.vndf_res; ++y)
                for (int x = 0; x < s.vndf_res; ++x) {
                    Float u = grid(x, s.vndf_res);
                    Vec3 wm = dir_of(u, grid(y, s.vndf_res), rel);
                    Float jac = 2 * kPi * kPi * u * std::sin(measured_u_to_theta(u));
                    slice.push_back(std::max(Float(0), dot(wo, wm)) * mf.D(wm) * jac);
                }
            vndf.insert(vndf.end(), slice.begin(), slice.end());
            PiecewiseLinear2D warp(slice, s.vndf_res, s.vndf_res, {}, true);
            // fr at each u' of the spectral grid, for every wavelength.
            const int n = s.spectra_res;
            std::vector<float> fr(size_t(nl) * n * n), lum(size_t(n) * n);
            for (int y = 0; y < n; ++y)
                for (int x = 0; x < n; ++x) {
                    Point2 m = warp.sample({grid(x, n), grid(y, n)}).p;
                    Vec3 wm = dir_of(m.x, m.y, rel);
                    Vec3 wi = 2 * dot(wo, wm) * wm - wo;
                    Float g = wi.z > 0 ? mf.G(wo, wi) / mf.G1(wo) : 0;
                    double sum = 0;
                    for (int l = 0; l < nl; ++l) {
                        Float v = g * standin_fresnel(s.f0[l], dot(wo, wm));
                        fr[(size_t(l) * n + y) * n + x] = v;
                        sum += v;
                    }
                    lum[size_t(y) * n + x] = float(sum / nl);
                }
            spectra.insert(spectra.end(), fr.begin(), fr.end());
            luminance.insert(luminance.end(), lum.begin(), lum.end());
        }

    const uint64_t np = phi_i.size(), nt = theta_i.size(), nw = uint64_t(nl);
    const uint64_t nd = uint64_t(s.ndf_res), nv = uint64_t(s.vndf_res),
                   ns = uint64_t(s.spectra_res);
    TensorFile f;
    f.fields["theta_i"] = float32_field({nt}, theta_i);
    f.fields["phi_i"] = float32_field({np}, phi_i);
    f.fields["wavelengths"] = float32_field({nw}, s.wavelengths);
    f.fields["ndf"] = float32_field({nd, nd}, ndf);
    f.fields["sigma"] = float32_field({nd, nd}, sigma);
    f.fields["vndf"] = float32_field({np, nt, nv, nv}, vndf);
    f.fields["luminance"] = float32_field({np, nt, ns, ns}, luminance);
    f.fields["spectra"] = float32_field({np, nt, nw, ns, ns}, spectra);
    TensorField jac;
    jac.dtype = TensorDtype::UInt8;
    jac.shape = {1};
    jac.bytes = std::string(1, '\1');
    f.fields["jacobian"] = jac;
    TensorField desc;
    desc.dtype = TensorDtype::UInt8;
    std::string text = "steradian stand-in: GGX conductor with Schlick Fresnel";
    desc.shape = {text.size()};
    desc.bytes = text;
    f.fields["description"] = desc;
    return f;
}

inline std::string standin_bytes(const StandinSpec& s) {
    return write_tensor_file(standin_tensor(s));
}

}  // namespace sr::test
