// Feeds arbitrary bytes to the NanoVDB reader (NanoVdbFile::parse, media/nanovdb.h) as the
// contents of a .nvdb file, and checks that an accepted grid samples to finite values inside
// and around its bounds and gives finite majorants.
#include "steradian/media/nanovdb.h"

#include "fuzz_target.h"
#include "steradian/media/medium.h"

STERADIAN_FUZZ_TARGET(nanovdb) {
    try {
        sr::NanoVdbFile f = sr::NanoVdbFile::parse(input, "fuzz.nvdb", "density", "temperature");
        for (const auto* g : {f.density.get(), f.temperature.get()}) {
            if (!g) continue;
            sr::Point3 lo = g->world_min(), hi = g->world_max();
            for (int i = 0; i <= 8; ++i) {
                float t = float(i) / 8 * 1.5f - 0.25f;  // from before lo to beyond hi
                sr::Point3 p = lo + (hi - lo) * sr::Point3(t, 1 - t, t * t);
                sr::fuzz::check_finite(g->sample(p), "sample");
            }
            sr::MajorantGrid m;
            m.res = 8;
            g->fill_majorants(m, lo, hi);
            for (float v : m.cells) sr::fuzz::check_finite(v, "majorant");
        }
    } catch (const sr::Error& e) {
        sr::fuzz::check_names_input(e, "fuzz.nvdb");
    }
}
