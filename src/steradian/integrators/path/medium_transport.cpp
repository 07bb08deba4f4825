#include "steradian/integrators/path/medium_transport.h"

#include <algorithm>

#include "steradian/media/medium.h"
#include "steradian/sampling/hash.h"
#include "steradian/scene/scene.h"

namespace sr {

Pcg32 tracking_rng(uint64_t a, uint64_t b) { return Pcg32(hash(a), hash(b)); }

int medium_after(const Scene& scene, const SurfaceHit& hit, Vec3 w, int current) {
    if (hit.shape < 0) return current;  // a vertex of no shape (a meter's receiver)
    const ShapeEntry& e = scene.shapes[size_t(hit.shape)];
    if (!e.medium_transition()) return current;
    return dot(w, hit.ng) > 0 ? e.medium_outside : e.medium_inside;
}

FreeFlight free_flight(const Scene& scene, int medium, const Ray& ray, Float t_max, Float u,
                       Float uk, const SampledWavelengths& lambda, SampledSpectrum& beta,
                       Point3& p, Float& g) {
    Pcg32 rng = tracking_rng(hash(uk, ray.o.x, ray.o.y, ray.o.z), hash(ray.d.x, ray.d.y, ray.d.z));
    bool scattered = false, absorbed = false;
    const SampledSpectrum t_maj = sample_t_maj(
        scene.media[size_t(medium)], ray, t_max, u, rng, lambda,
        [&](Point3 pc, const MediumProperties& mp, SampledSpectrum sigma_maj, SampledSpectrum tm) {
            // Absorption, real or null scattering, with the hero wavelength's probabilities.
            const Float p_absorb = mp.sigma_a[0] / sigma_maj[0];
            const Float p_real = mp.sigma_s[0] / sigma_maj[0];
            const Float um = rng.next_float();
            if (um < p_absorb) {
                absorbed = true;
                return false;
            }
            if (um < p_absorb + p_real) {
                beta *= tm * mp.sigma_s / (tm[0] * mp.sigma_s[0]);
                p = pc;
                g = mp.g;
                scattered = true;
                return false;
            }
            SampledSpectrum sigma_n = sigma_maj - mp.sigma_a - mp.sigma_s;
            for (int i = 0; i < kSpectrumSamples; ++i) sigma_n[i] = std::max(sigma_n[i], Float(0));
            const Float pdf = tm[0] * sigma_n[0];
            beta = pdf > 0 ? beta * tm * sigma_n / pdf : SampledSpectrum(0);
            return !beta.is_zero();
        });
    if (absorbed || beta.is_zero() || beta.has_nonfinite()) return FreeFlight::Absorbed;
    if (scattered) return FreeFlight::Scattered;
    beta *= t_maj / t_maj[0];
    if (beta.is_zero() || beta.has_nonfinite()) return FreeFlight::Absorbed;
    return FreeFlight::Passed;
}

SampledSpectrum shadow_transmittance(const Scene& scene, Ray ray, int medium, bool to_point,
                                     const SampledWavelengths& lambda, SampledSpectrum& r_l,
                                     SampledSpectrum& r_u, uint64_t key, PathCounters& counters) {
    const Point3 end = ray.o + ray.d;  // the target of a ray to a point (t_max < 1)
    SampledSpectrum t_ray(1);
    Pcg32 rng = tracking_rng(hash(ray.o.x, ray.o.y, ray.o.z, key), hash(ray.d.x, ray.d.y, ray.d.z));
    SurfaceHit h;
    for (int crossings = 0; crossings <= 256; ++crossings) {
        ++counters.rays;
        const bool found = scene.intersect(ray, h);
        if (found && h.material >= 0) return SampledSpectrum(0);
        if (medium >= 0) {
            Float t_max = found ? h.t : ray.t_max;
            SampledSpectrum t_maj = sample_t_maj(
                scene.media[size_t(medium)], ray, t_max, rng.next_float(), rng, lambda,
                [&](Point3, const MediumProperties& mp, SampledSpectrum sigma_maj,
                    SampledSpectrum tm) {
                    SampledSpectrum sigma_n = sigma_maj - mp.sigma_a - mp.sigma_s;
                    for (int i = 0; i < kSpectrumSamples; ++i)
                        sigma_n[i] = std::max(sigma_n[i], Float(0));
                    Float pdf = tm[0] * sigma_maj[0];
                    t_ray *= tm * sigma_n / pdf;
                    r_l *= tm * sigma_maj / pdf;
                    r_u *= tm * sigma_n / pdf;
                    // Russian roulette on low transmittance (unbiased).
                    SampledSpectrum tr = t_ray / (r_l + r_u).average();
                    if (tr.max_value() < Float(0.05)) {
                        if (rng.next_float() < Float(0.75))
                            t_ray = SampledSpectrum(0);
                        else
                            t_ray /= Float(0.25);
                    }
                    return !t_ray.is_zero();
                });
            t_ray *= t_maj / t_maj[0];
            r_l *= t_maj / t_maj[0];
            r_u *= t_maj / t_maj[0];
            if (t_ray.has_nonfinite()) return SampledSpectrum(0);
        }
        if (t_ray.is_zero()) return SampledSpectrum(0);
        if (!found) return t_ray;
        medium = medium_after(scene, h, ray.d, medium);
        ray = to_point ? spawn_ray_to(h, end) : spawn_ray(h, ray.d);
    }
    return SampledSpectrum(0);
}

}  // namespace sr
