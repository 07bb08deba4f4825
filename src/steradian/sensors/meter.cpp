#include "steradian/sensors/meter.h"

#include "steradian/spectrum/spectrum.h"

namespace sr {

std::string Meter::unit() const {
    bool radiometric = weighting == MeterWeighting::Radiometric;
    if (glare) return "UGR";
    if (kind == MeterKind::Luminance) return radiometric ? "W/(m2 sr)" : "cd/m2";
    return radiometric ? "W/m2" : "lx";
}

Float Meter::spectral_weight(Float lambda) const {
    switch (weighting) {
        case MeterWeighting::Photopic: return cie_y()(lambda);
        case MeterWeighting::Scotopic:
            return Float(kKmScotopic / kKmPhotopic) * cie_scotopic_v()(lambda);
        case MeterWeighting::Radiometric: return Float(1 / kKmPhotopic);
    }
    return 0;
}

}  // namespace sr
