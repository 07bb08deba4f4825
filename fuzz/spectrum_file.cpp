// Feeds arbitrary bytes to the spectrum file reader (parse_spectrum_file, scene/build.h) as
// the text of a two-column "wavelength value" file, then turns accepted samples into the
// spectrum the builder makes of them and checks that it is finite at every wavelength and in
// its XYZ.
#include "fuzz_target.h"
#include "steradian/scene/build.h"

STERADIAN_FUZZ_TARGET(spectrum_file) {
    using sr::fuzz::check_finite;
    const std::string name = "fuzz.spd";
    try {
        std::vector<sr::Float> pairs =
            sr::parse_spectrum_file(input, name, sr::SourceLoc{"fuzz.pbrt", 1, 1});
        sr::fuzz::fuzz_check(pairs.size() >= 4 && pairs.size() % 2 == 0, "pair count");
        sr::Spectrum s = sr::densely_sampled(sr::piecewise_linear_from_interleaved(pairs, false));
        for (int lambda = 360; lambda <= 830; ++lambda)
            check_finite(s(sr::Float(lambda)), "spectrum value");
        check_finite(s.max_value(), "max_value()");
        sr::Xyz xyz = sr::spectrum_to_xyz(s);
        check_finite(xyz.x, "X");
        check_finite(xyz.y, "Y");
        check_finite(xyz.z, "Z");
    } catch (const sr::Error& e) {
        sr::fuzz::check_names_input(e, name);
    }
}
