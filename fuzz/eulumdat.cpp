// Feeds arbitrary bytes to the EULUMDAT reader (parse_eulumdat,
// lights/photometric/eulumdat.h) as the text of an .ldt file, and checks that an accepted
// file gives finite intensities and flux.
#include "steradian/lights/photometric/eulumdat.h"

#include "photometric_common.h"

STERADIAN_FUZZ_TARGET(eulumdat) {
    const std::string name = "fuzz.ldt";
    try {
        sr::fuzz::check_photometric(sr::parse_eulumdat(input, name));
    } catch (const sr::Error& e) {
        sr::fuzz::check_names_input(e, name);
    }
}
