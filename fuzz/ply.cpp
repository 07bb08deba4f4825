// Feeds arbitrary bytes to the PLY reader (parse_ply, scene/mesh_io/ply.h) as a whole .ply
// file, ASCII or binary (the seeds have both); an accepted mesh must satisfy validate().
#include "steradian/scene/mesh_io/ply.h"

#include "fuzz_target.h"

STERADIAN_FUZZ_TARGET(ply) {
    const std::string name = "fuzz.ply";
    try {
        sr::TriangleMeshData mesh = sr::parse_ply(input, name);
        try {
            sr::validate(mesh, name);
        } catch (const sr::Error&) {
            sr::fuzz::fuzz_check(false, "parse_ply returned a mesh that validate() rejects");
        }
    } catch (const sr::Error& e) {
        sr::fuzz::check_names_input(e, name);
    }
}
