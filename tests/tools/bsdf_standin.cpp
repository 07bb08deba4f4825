// steradian_bsdf_standin: writes a stand-in .bsdf file (tests/support/measured_standin.h: the
// tables of a GGX conductor with Schlick's Fresnel term) for renders and fuzzing seeds, since
// the RGL database's files cannot be downloaded everywhere.
//
// Usage: steradian_bsdf_standin OUT.bsdf [alpha_x [alpha_y [grid]]]
//   alpha_y != alpha_x writes an anisotropic table (9 phi_i); grid sets the vndf, spectra and
//   luminance resolution (ndf and sigma get twice it); small grids make small files.
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

#include "steradian/core/output_file.h"
#include "support/measured_standin.h"

int main(int argc, char** argv) {
    if (argc < 2 || argc > 5) {
        std::fprintf(stderr, "usage: %s OUT.bsdf [alpha_x [alpha_y [grid]]]\n", argv[0]);
        return 2;
    }
    sr::test::StandinSpec s;
    if (argc > 2) s.alpha_x = s.alpha_y = std::strtof(argv[2], nullptr);
    if (argc > 3) s.alpha_y = std::strtof(argv[3], nullptr);
    s.anisotropic = s.alpha_x != s.alpha_y;
    if (argc > 4) {
        int g = std::atoi(argv[4]);
        s.vndf_res = s.spectra_res = g;
        s.ndf_res = 2 * g;
        s.n_theta_i = std::max(2, g / 3);
        s.n_phi_i = std::max(3, g / 3);
    }
    if (!(s.alpha_x > 0 && s.alpha_y > 0) || s.vndf_res < 2) {
        std::fprintf(stderr, "alpha must be > 0 and grid >= 2\n");
        return 2;
    }
    try {
        sr::write_text_file(argv[1], sr::test::standin_bytes(s));  // any bytes
    } catch (const std::exception& e) {
        std::fprintf(stderr, "%s\n", e.what());
        return 1;
    }
    return 0;
}
