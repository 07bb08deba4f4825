// Feeds arbitrary bytes to the IES LM-63 reader (parse_ies,
// lights/photometric/ies.h) as the text of an .ies file, and checks that an accepted file
// gives finite intensities, flux and tilt factors.
#include "steradian/lights/photometric/ies.h"

#include "photometric_common.h"

STERADIAN_FUZZ_TARGET(ies) {
    // TILT=<file> resolves beside the input's name: a directory of the project's test data.
    static const std::string name = STERADIAN_SOURCE_DIR "/tests/data/identical/fuzz.ies";
    try {
        sr::fuzz::check_photometric(sr::parse_ies(input, name));
    } catch (const sr::Error& e) {
        sr::fuzz::check_names_input(e, "fuzz.ies");
    }
}
