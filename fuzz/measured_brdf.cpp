// Feeds arbitrary bytes to the measured BRDF reader (parse_measured_brdf, bsdf/measured.h) as
// the contents of a .bsdf tensor file, and checks that an accepted file gives a lobe whose
// f(), pdf() and sample() are finite and non-negative for a spread of directions.
#include "fuzz_target.h"
#include "steradian/bsdf/measured.h"

STERADIAN_FUZZ_TARGET(measured_brdf) {
    using sr::fuzz::fuzz_check;
    const std::string name = "fuzz.bsdf";
    try {
        sr::MeasuredBrdf b = sr::parse_measured_brdf(input, name);
        sr::SampledWavelengths lambda;
        lambda.lambda = {380, 500, 640, 800};
        lambda.pdf = {1, 1, 1, 1};
        sr::MeasuredLobe lobe{&b, lambda};
        const sr::Vec3 dirs[] = {{0, 0, 1},
                                 {0.6f, 0, 0.8f},
                                 {-0.3f, 0.4f, 0.866f},
                                 {0.99f, 0.1f, 0.1f},
                                 {0.2f, -0.2f, -0.959f}};
        for (sr::Vec3 wo : dirs) {
            wo = sr::normalize(wo);
            for (sr::Vec3 wi : dirs) {
                wi = sr::normalize(wi);
                sr::SampledSpectrum f = lobe.f(wo, wi, sr::TransportMode::Radiance);
                fuzz_check(!f.has_nonfinite() && f.min_value() >= 0, "f finite, >= 0");
                sr::Float p = lobe.pdf(wo, wi, sr::TransportMode::Radiance);
                fuzz_check(std::isfinite(p) && p >= 0, "pdf finite, >= 0");
            }
            for (sr::Float u : {0.0f, 0.3f, 0.999f}) {
                auto s = lobe.sample(wo, 0.5f, {u, 1 - u}, sr::TransportMode::Radiance);
                if (!s) continue;
                fuzz_check(!s->f.has_nonfinite() && s->f.min_value() >= 0, "sample f");
                fuzz_check(std::isfinite(s->pdf_sa) && s->pdf_sa > 0, "sample pdf");
                fuzz_check(std::abs(sr::length(s->wi) - 1) < 1e-3f, "sample wi unit");
            }
        }
    } catch (const sr::Error& e) {
        sr::fuzz::check_names_input(e, name);
    }
}
