#pragma once
/// The BSDF at a surface point: one lobe (a std::variant of plain structs, each satisfying
/// the Lobe concept) in a shading frame. World-space wrappers convert directions and
/// enforce the geometric-normal side test against light leaks.
#include <array>
#include <concepts>
#include <type_traits>
#include <utility>
#include <variant>

#include "steradian/bsdf/bxdf_common.h"
#include "steradian/bsdf/conductor.h"
#include "steradian/bsdf/dielectric.h"
#include "steradian/bsdf/diffuse_transmission.h"
#include "steradian/bsdf/hair.h"
#include "steradian/bsdf/lafortune.h"
#include "steradian/bsdf/lambert.h"
#include "steradian/bsdf/layered.h"
#include "steradian/bsdf/measured.h"
#include "steradian/bsdf/normalized_fresnel.h"
#include "steradian/bsdf/phong.h"
#include "steradian/bsdf/thin_dielectric.h"
#include "steradian/bsdf/ward.h"

namespace sr {

template <typename L>
concept Lobe = requires(const L& l, Vec3 w, Float uc, Point2 u, TransportMode m) {
    { l.f(w, w, m) } -> std::same_as<SampledSpectrum>;
    { l.sample(w, uc, u, m) } -> std::same_as<std::optional<BsdfSample>>;
    { l.pdf(w, w, m) } -> std::same_as<Float>;
    { l.flags() } -> std::same_as<uint8_t>;
};

using LobeVariant =
    std::variant<LambertLobe, DielectricLobe, ThinDielectricLobe, ConductorLobe,
                 DiffuseTransmissionLobe, PhongLobe, LafortuneLobe, WardLobe, CoatedDiffuseLobe,
                 CoatedConductorLobe, HairLobe, MeasuredLobe, NormalizedFresnelLobe>;
/// Whether a lobe's sample() reads its 1D sample uc; a lobe that does not says so with
/// `static constexpr bool kIgnoresUc = true`.
template <typename L>
inline constexpr bool kLobeUsesUc = !requires { requires L::kIgnoresUc; };

static_assert(Lobe<LambertLobe>);
static_assert(Lobe<DielectricLobe>);
static_assert(Lobe<ThinDielectricLobe>);
static_assert(Lobe<ConductorLobe>);
static_assert(Lobe<DiffuseTransmissionLobe>);
static_assert(Lobe<PhongLobe>);
static_assert(Lobe<LafortuneLobe>);
static_assert(Lobe<WardLobe>);
static_assert(Lobe<CoatedDiffuseLobe>);
static_assert(Lobe<CoatedConductorLobe>);
static_assert(Lobe<HairLobe>);
static_assert(Lobe<MeasuredLobe>);
static_assert(Lobe<NormalizedFresnelLobe>);

class Bsdf {
  public:
    Bsdf() = default;
    /// The lobe is built in place in the variant (a LobeVariant argument would be built and
    /// then copied whole).
    template <typename L>
        requires Lobe<std::decay_t<L>>
    Bsdf(const Frame& shading, Normal3 ng, L&& lobe)
        : m_frame(shading),
          m_ng(ng),
          m_lobe(std::in_place_type<std::decay_t<L>>, std::forward<L>(lobe)) {}
    /// From a lobe already held in a variant.
    Bsdf(const Frame& shading, Normal3 ng, const LobeVariant& lobe)
        : m_frame(shading), m_ng(ng), m_lobe(lobe) {}

    uint8_t flags() const {
        return std::visit([](const auto& l) { return l.flags(); }, m_lobe);
    }
    bool is_specular_only() const {
        uint8_t f = flags();
        return (f & kLobeSpecular) && !(f & (kLobeDiffuse | kLobeGlossy));
    }
    bool has_non_specular() const { return flags() & (kLobeDiffuse | kLobeGlossy); }
    /// Whether sample() reads uc: if not, the caller may skip computing it (Sampler::skip_1d).
    bool uses_uc() const { return kUsesUc[m_lobe.index()]; }

    /// f(wo, wi) for world-space unit directions (no cosine).
    SampledSpectrum f(Vec3 wo_w, Vec3 wi_w, TransportMode mode = TransportMode::Radiance) const {
        Vec3 wo = m_frame.to_local(wo_w), wi = m_frame.to_local(wi_w);
        if (wo.z == 0) return SampledSpectrum(0);
        return std::visit([&](const auto& l) { return l.f(wo, wi, mode); }, m_lobe) *
               adjoint_factor(wo_w, wi_w, mode);
    }

    /// Veach's correction for shading normals in importance transport (Veach 1997, sec.
    /// 5.3.4, eq. 5.19): the adjoint BSDF with shading normals is not the BSDF with its
    /// arguments swapped, but f* = f |wo . ns| |wi . ng| / (|wo . ng| |wi . ns|), wo being
    /// the direction towards the previous vertex of the light path. 1 for radiance.
    Float adjoint_factor(Vec3 wo_w, Vec3 wi_w, TransportMode mode) const {
        if (mode == TransportMode::Radiance) return 1;
        Float num = std::abs(dot(wo_w, m_frame.n)) * std::abs(dot(wi_w, m_ng));
        Float den = std::abs(dot(wo_w, m_ng)) * std::abs(dot(wi_w, m_frame.n));
        return den == 0 ? 0 : num / den;
    }
    /// f(wo, wi), the solid-angle pdf of sampling wi given wo, and |cos| of wi with the
    /// shading normal: what next-event estimation with MIS needs, with one change of frame.
    struct Eval {
        SampledSpectrum f;
        Float pdf_sa = 0;
        Float abs_cos = 0;
    };
    Eval evaluate(Vec3 wo_w, Vec3 wi_w, TransportMode mode = TransportMode::Radiance) const {
        Vec3 wo = m_frame.to_local(wo_w), wi = m_frame.to_local(wi_w);
        if (wo.z == 0) return {};
        return std::visit(
            [&](const auto& l) {
                return Eval{l.f(wo, wi, mode) * adjoint_factor(wo_w, wi_w, mode),
                            l.pdf(wo, wi, mode), std::abs(wi.z)};
            },
            m_lobe);
    }
    /// Samples wi given wo (world space); the returned wi is world space.
    std::optional<BsdfSample> sample(Vec3 wo_w, Float uc, Point2 u,
                                     TransportMode mode = TransportMode::Radiance) const {
        Vec3 wo = m_frame.to_local(wo_w);
        // Every return returns s, so that it is the caller's object (with an early
        // `return std::nullopt` the compiler built s locally and copied it out).
        std::optional<BsdfSample> s =
            wo.z != 0 ? std::visit([&](const auto& l) { return l.sample(wo, uc, u, mode); }, m_lobe)
                      : std::nullopt;
        if (s && (s->f.is_zero() || s->pdf_sa == 0 || s->wi.z == 0)) s.reset();
        if (s) {
            s->wi = m_frame.to_world(s->wi);
            if (mode == TransportMode::Importance) s->f *= adjoint_factor(wo_w, s->wi, mode);
        }
        return s;
    }
    /// Solid-angle pdf of sampling wi given wo (world space).
    Float pdf(Vec3 wo_w, Vec3 wi_w, TransportMode mode = TransportMode::Radiance) const {
        Vec3 wo = m_frame.to_local(wo_w), wi = m_frame.to_local(wi_w);
        if (wo.z == 0) return 0;
        return std::visit([&](const auto& l) { return l.pdf(wo, wi, mode); }, m_lobe);
    }
    /// Widens the microfacet distributions as pbrt-v4's BSDF::Regularize does (see
    /// TrowbridgeReitz::regularize): dielectric and conductor lobes, and both layers of the
    /// coated ones. Diffuse, thin dielectric, hair, measured and the classic lobes are left
    /// as they are (pbrt-v4's are no-ops too; its thin dielectric's is a TODO).
    void regularize() {
        std::visit(
            [](auto& l) {
                using L = std::decay_t<decltype(l)>;
                if constexpr (std::is_same_v<L, DielectricLobe> || std::is_same_v<L, ConductorLobe>)
                    l.mf.regularize();
                else if constexpr (std::is_same_v<L, CoatedDiffuseLobe>)
                    l.top.mf.regularize();
                else if constexpr (std::is_same_v<L, CoatedConductorLobe>) {
                    l.top.mf.regularize();
                    l.bottom.mf.regularize();
                }
            },
            m_lobe);
    }
    const Frame& frame() const { return m_frame; }
    Normal3 ng() const { return m_ng; }
    const LobeVariant& lobe() const { return m_lobe; }

  private:
    static constexpr auto kUsesUc = []<std::size_t... I>(std::index_sequence<I...>) {
        return std::array<bool, sizeof...(I)>{
            kLobeUsesUc<std::variant_alternative_t<I, LobeVariant>>...};
    }(std::make_index_sequence<std::variant_size_v<LobeVariant>>());

    Frame m_frame;
    Normal3 m_ng;
    LobeVariant m_lobe;
};

}  // namespace sr
