#pragma once
/// Published CIE tables used by the spectrum module (internal to src/steradian/spectrum/).
/// Each table cites its source in cie_data.cpp.

namespace sr::cie {

/// CIE 1931 2-degree colour matching functions at 1 nm, 360..830 nm (471 values each).
inline constexpr int kCmfFirstNm = 360;
inline constexpr int kCmfCount = 471;
extern const float kX[kCmfCount];
extern const float kY[kCmfCount];
extern const float kZ[kCmfCount];

/// Daylight basis S0, S1, S2 and the tabulated illuminant D65, at 10 nm, 300..830 nm
/// (54 values each). CIE 015 interpolates them linearly to finer steps.
inline constexpr int kDaylightFirstNm = 300;
inline constexpr int kDaylightStepNm = 10;
inline constexpr int kDaylightCount = 54;
extern const float kS0[kDaylightCount];
extern const float kS1[kDaylightCount];
extern const float kS2[kDaylightCount];
extern const float kD65[kDaylightCount];

/// Fluorescent illuminants F1..F12 at 5 nm, 380..780 nm (81 values each), relative.
inline constexpr int kFluorescentFirstNm = 380;
inline constexpr int kFluorescentStepNm = 5;
inline constexpr int kFluorescentCount = 81;
extern const float kF[12][kFluorescentCount];

/// CIE 1951 scotopic luminous efficiency function V'(lambda) at 1 nm, 380..780 nm (401 values).
inline constexpr int kScotopicFirstNm = 380;
inline constexpr int kScotopicCount = 401;
extern const float kScotopicV[kScotopicCount];

/// High-pressure discharge lamp illuminants HP1..HP5 (CIE 015:2018) at 5 nm, 380..780 nm
/// (81 values each), relative.
inline constexpr int kHpFirstNm = 380;
inline constexpr int kHpStepNm = 5;
inline constexpr int kHpCount = 81;
inline constexpr int kHpIlluminants = 5;
extern const float kHp[kHpIlluminants][kHpCount];

/// LED illuminants (CIE 015:2018) at 5 nm, 380..780 nm (81 values each), relative, in the
/// order LED-B1, LED-B2, LED-B3, LED-B4, LED-B5, LED-BH1, LED-RGB1, LED-V1, LED-V2.
inline constexpr int kLedFirstNm = 380;
inline constexpr int kLedStepNm = 5;
inline constexpr int kLedCount = 81;
inline constexpr int kLedIlluminants = 9;
extern const float kLed[kLedIlluminants][kLedCount];

}  // namespace sr::cie
