/// pbrt-v4's names of the sample randomizations (sobol.h's Randomization).
#include "steradian/sampling/sobol.h"

#include "steradian/core/error.h"

namespace sr {

Randomization randomization_from_string(const std::string& name) {
    if (name == "none") return Randomization::kNone;
    if (name == "permutedigits") return Randomization::kXor;
    if (name == "fastowen" || name == "owen") return Randomization::kOwen;
    throw Error(fmt::format(
        "unknown sample randomization \"{}\" (expected none, permutedigits, fastowen or owen)",
        name));
}

std::string to_string(Randomization r) {
    switch (r) {
        case Randomization::kNone:
            return "none";
        case Randomization::kXor:
            return "permutedigits";
        case Randomization::kOwen:
            return "owen";
    }
    return "?";
}

}  // namespace sr
