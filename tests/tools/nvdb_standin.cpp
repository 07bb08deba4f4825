// steradian_nvdb_standin: writes a small stand-in NanoVDB file (a ball of density in 16^3
// voxels, made with NanoVDB's own API: tests/support/nvdb_writer.h) for the pbrt-v4 scenes
// whose .nvdb grids are not at hand (scripts/pbrt_corpus.py) and for the fuzzing seeds.
//
// Usage: steradian_nvdb_standin OUT.nvdb [--temperature] [--zip]
//   --temperature adds a "temperature" grid (the same ball, 20 at its centre);
//   --zip writes the grids ZIP-compressed.
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <string>

#include "support/nvdb_writer.h"

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: %s OUT.nvdb [--temperature] [--zip]\n", argv[0]);
        return 2;
    }
    bool temperature = false;
    auto codec = nanovdb::io::Codec::NONE;
    for (int i = 2; i < argc; ++i) {
        if (std::strcmp(argv[i], "--temperature") == 0) {
            temperature = true;
        } else if (std::strcmp(argv[i], "--zip") == 0) {
            codec = nanovdb::io::Codec::ZIP;
        } else {
            std::fprintf(stderr, "%s: unknown option %s\n", argv[0], argv[i]);
            return 2;
        }
    }
    // A ball of radius 7 voxels about (7.5, 7.5, 7.5), falling smoothly to 0 at its edge.
    auto ball = [](float peak) {
        return [peak](int i, int j, int k) {
            float r = std::sqrt(float((i - 7.5) * (i - 7.5) + (j - 7.5) * (j - 7.5) +
                                      (k - 7.5) * (k - 7.5))) / 7;
            return r < 1 ? peak * (1 - r * r) : 0.0f;
        };
    };
    std::vector<sr::test::NvdbGridSpec> grids(1);
    grids[0].name = "density";
    grids[0].value = ball(1);
    grids[0].hi = nanovdb::Coord(15);
    grids[0].voxel = 1.0 / 16;
    if (temperature) {
        grids.push_back(grids[0]);
        grids[1].name = "temperature";
        grids[1].value = ball(20);
    }
    try {
        sr::test::write_nvdb(argv[1], grids, codec);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "%s: %s\n", argv[0], e.what());
        return 1;
    }
    return 0;
}
