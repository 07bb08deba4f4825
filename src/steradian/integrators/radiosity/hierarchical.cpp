#include "steradian/integrators/radiosity/hierarchical.h"

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <chrono>
#include <stdexcept>
#include <tuple>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "steradian/core/math.h"
#include "steradian/sampling/hash.h"
#include "steradian/sampling/warp.h"

namespace sr::radiosity {

namespace {

struct Link {
    int p, q;   ///< the two nodes
    double s;   ///< the exchange A_p F_pq = A_q F_qp
};

/// Visibility between two patches as the fraction of n rays that pass, between points
/// uniformly distributed over each (the R2 sequence, shifted by a hash of the pair): an
/// unbiased estimate of the mean visibility (fixed quadrature points would repeat the same
/// error over the many congruent pairs of a mesh).
/// With `all_or_none`, the rays stop at the first packet with a blocked ray (the result is
/// then only compared with 1: whether all n pass).
double visible_fraction(const PatchGeom& a, const PatchGeom& b, uint64_t key, double eps,
                        const Visibility& vis, const VisibilityBatch& batch, uint64_t& rays,
                        int n, bool all_or_none = false) {
    int pass = 0;
    DVec3 from[8], to[8];
    for (int i0 = 0; i0 < n; i0 += 8) {
        const int m = std::min(8, n - i0);
        for (int j = 0; j < m; ++j) {
            const uint64_t i = uint64_t(i0 + j);
            const auto ba = sample_uniform_triangle(r2(i, key));
            const auto bb = sample_uniform_triangle(r2(i, ~key));
            from[j] = a.v[0] * double(ba[0]) + a.v[1] * double(ba[1]) + a.v[2] * double(ba[2]) +
                      a.n * eps;
            to[j] = b.v[0] * double(bb[0]) + b.v[1] * double(bb[1]) + b.v[2] * double(bb[2]) +
                    b.n * eps;
        }
        rays += uint64_t(m);
        if (batch) {
            pass += std::popcount(batch(from, to, m));
        } else {
            for (int j = 0; j < m; ++j) pass += vis(from[j], to[j]) ? 1 : 0;
        }
        if (all_or_none && pass < i0 + m) return 0;
    }
    return double(pass) / double(n);
}

constexpr int kWholeRays = 16, kLinkRays = 4;

}  // namespace

std::vector<double> solve_hierarchical(const std::vector<HierNode>& nodes,
                                       const std::vector<int>& roots, const std::vector<double>& rho,
                                       const std::vector<double>& E, const std::vector<double>& ybar,
                                       const Visibility& visible, const HierParams& prm,
                                       tbb::task_arena& arena, HierStats& st,
                                       const VisibilityBatch& visible_batch) {
    const size_t nb = ybar.size();
    if (nb > 64) throw std::logic_error("solve_hierarchical: at most 64 bands");
    const size_t nn = nodes.size();
    size_t nu = 0;
    for (const HierNode& n : nodes) nu = std::max(nu, size_t(n.unknown + 1));

    // ---- estimated exitance for the refinement -------------------------------------------------
    // B ~ rho (E + E_amb) with the enclosure's ambient estimate E_amb = (area mean of rho E) /
    // (1 - area mean of rho), per band; photopic; nodes take their children's area mean.
    std::vector<double> Y(nn, 0), Ylo(nn, 0), Yhi(nn, 0);
    double rho_mean = 0;  // the largest band's area mean of the reflectance
    {
        std::vector<double> sum_rhoE(nb, 0), sum_rho(nb, 0);
        double area = 0;
        for (const HierNode& n : nodes) {
            if (n.unknown < 0) continue;
            area += n.g.area;
            for (size_t k = 0; k < nb; ++k) {
                const double r = rho[size_t(n.unknown) * nb + k];
                sum_rhoE[k] += n.g.area * r * E[size_t(n.unknown) * nb + k];
                sum_rho[k] += n.g.area * r;
            }
        }
        std::vector<double> amb(nb, 0);
        for (size_t k = 0; k < nb && area > 0; ++k) {
            amb[k] = (sum_rhoE[k] / area) / std::max(1e-3, 1 - sum_rho[k] / area);
            rho_mean = std::max(rho_mean, sum_rho[k] / area);
        }
        // Children follow their parents in `nodes` (their index is larger): one backward pass.
        for (size_t i = nn; i-- > 0;) {
            const HierNode& n = nodes[i];
            if (n.child < 0) {
                double y = 0;
                for (size_t k = 0; k < nb; ++k)
                    y += ybar[k] * rho[size_t(n.unknown) * nb + k] *
                         (E[size_t(n.unknown) * nb + k] + amb[k]);
                Y[i] = Ylo[i] = Yhi[i] = y;
            } else {
                double s = 0;
                Ylo[i] = kInfinity;
                Yhi[i] = 0;
                for (int c = 0; c < 4; ++c) {
                    const size_t ci = size_t(n.child + c);
                    s += nodes[ci].g.area * Y[ci];
                    Ylo[i] = std::min(Ylo[i], Ylo[ci]);
                    Yhi[i] = std::max(Yhi[i], Yhi[ci]);
                }
                Y[i] = n.g.area > 0 ? s / n.g.area : 0;
            }
        }
    }
    // The scale of the errors: the area mean of the estimated exitance.
    double power = 0, total_area = 0;
    for (int r : roots) {
        power += nodes[size_t(r)].g.area * Y[size_t(r)];
        total_area += nodes[size_t(r)].g.area;
    }
    // The interreflections multiply an error of the gathered light by up to 1 / (1 - rho):
    // the bound is tightened by (1 - rho) so that it holds for the solution.
    const double eps_irr = prm.link_error * std::max(1e-3, 1 - rho_mean) *
                           std::max(power / std::max(total_area, 1e-300), 1e-300);

    // ---- links: BF refinement of every facing pair of roots ----------------------------------
    std::vector<std::vector<Link>> links_of(roots.size());
    std::atomic<uint64_t> rays{0};
    arena.execute([&] {
        tbb::parallel_for(size_t(0), roots.size(), [&](size_t i) {
            std::vector<Link>& out = links_of[i];
            uint64_t my_rays = 0;
            // (p, q, whether p and q were found wholly visible to each other at a coarser level)
            std::vector<std::tuple<int, int, bool>> stack;
            for (size_t j = i + 1; j < roots.size(); ++j) {
                if (!facing(nodes[size_t(roots[i])].g, nodes[size_t(roots[j])].g, prm.eps))
                    continue;
                stack.push_back({roots[i], roots[j], false});
                while (!stack.empty()) {
                    // (Not a structured binding: clang 14 cannot capture one in a lambda.)
                    const int p = std::get<0>(stack.back()), q = std::get<1>(stack.back());
                    const bool seen = std::get<2>(stack.back());
                    stack.pop_back();
                    const HierNode& P = nodes[size_t(p)];
                    const HierNode& Q = nodes[size_t(q)];
                    // Unoccluded point-to-point estimate of the exchange, A_p A_q cos cos /
                    // (pi r^2), bounded by the smaller area (F <= 1); a pair nearer than its
                    // size, or whose centroids do not see each other, gets the bound.
                    const DVec3 d = Q.g.c - P.g.c;
                    const double r2 = ddot(d, d);
                    const double cp = ddot(P.g.n, d), cq = -ddot(Q.g.n, d);
                    const double bound = std::min(P.g.area, Q.g.area);
                    const double size = std::max(P.g.diam, Q.g.diam);
                    double s_est = bound;
                    if (cp > 0 && cq > 0 && r2 > size * size)
                        s_est = std::min(bound, P.g.area * Q.g.area * cp * cq / (kPi * r2 * r2));
                    // The error of a link, as irradiance at each end (BF refinement: Hanrahan
                    // et al.'s B F, with the form factor F_pq = S / A_p): the link moves each
                    // node's mean exitance, while the exitance spreads within the node (from
                    // the estimate's lowest to its highest leaf), and it spreads what it
                    // gathers evenly over the receiver, while the kernel varies across it by
                    // about the nodes' size over their distance (all of it when nearer).
                    const double dist = std::sqrt(r2);
                    const double var = std::min(1.0, size / std::max(dist, 1e-300));
                    const double f_pq = s_est / std::max(P.g.area, 1e-300);
                    const double f_qp = s_est / std::max(Q.g.area, 1e-300);
                    const double err_p =
                        f_pq * (Yhi[size_t(q)] - Ylo[size_t(q)] + var * Y[size_t(q)]);
                    const double err_q =
                        f_qp * (Yhi[size_t(p)] - Ylo[size_t(p)] + var * Y[size_t(p)]);
                    const double link_err = std::max(err_p, err_q);
                    // What the link carries, as irradiance, for the visibility test below.
                    const double carried =
                        std::max(f_pq * Y[size_t(q)], f_qp * Y[size_t(p)]);
                    const bool can_split = P.child >= 0 || Q.child >= 0;
                    // Split the larger node (that has children).
                    auto split = [&](bool whole) {
                        const bool split_p =
                            P.child >= 0 && (Q.child < 0 || P.g.area >= Q.g.area);
                        for (int c = 3; c >= 0; --c) {
                            const int a = split_p ? P.child + c : p;
                            const int b = split_p ? q : Q.child + c;
                            if (facing(nodes[size_t(a)].g, nodes[size_t(b)].g, prm.eps))
                                stack.push_back({a, b, whole});
                        }
                    };
                    // Visibility: the fraction of rays between the two that pass (none cast when a
                    // coarser pair containing these two was wholly visible).
                    auto visibility = [&](int n, bool all_or_none = false) {
                        return !visible || seen
                                   ? 1.0
                                   : visible_fraction(P.g, Q.g, hash(uint64_t(p), uint64_t(q)),
                                                      prm.eps, visible, visible_batch, my_rays,
                                                      n, all_or_none);
                    };
                    if (can_split && link_err > eps_irr) {
                        // 16 rays that all pass: the children are taken as wholly visible
                        // (the rays stop at the first blocked packet).
                        split(visibility(kWholeRays, true) == 1);
                        continue;
                    }
                    // A partly hidden pair that carries light is split; an unhidden one gets
                    // the unoccluded exchange; a partly hidden one that cannot be split, the
                    // exchange with a ray per quadrature point when near (else the fraction).
                    const double v = visibility(kLinkRays);
                    if (v > 0 && v < 1 && can_split && carried > eps_irr) {
                        split(false);
                        continue;
                    }
                    const bool near = !(std::min(P.g.diam, Q.g.diam) < 0.3 * dist &&
                                        std::max(P.g.diam, Q.g.diam) < dist);
                    // Three levels of the adaptive quadrature (exchange's 6 changed no reading
                    // of the office's grid, at twice the cost).
                    constexpr int levels = 3;
                    double s = 0;
                    if (v == 1)
                        s = exchange(P.g, Q.g, prm.eps, nullptr, nullptr, -1, levels);
                    else if (near)
                        s = exchange(P.g, Q.g, prm.eps, visible, &my_rays, -1, levels);
                    else if (v > 0)
                        s = v * exchange(P.g, Q.g, prm.eps, nullptr, nullptr, -1, levels);
                    if (s > 0) out.push_back({p, q, s});
                }
            }
            rays += my_rays;
        });
    });
    std::vector<Link> links;
    for (auto& l : links_of) links.insert(links.end(), l.begin(), l.end());
    links_of.clear();
    st.links = links.size();
    st.rays = rays;

    // ---- gather lists by receiver (counting sort, in link order: deterministic) ----------------
    std::vector<size_t> first(nn + 1, 0);
    for (const Link& l : links) {
        ++first[size_t(l.p) + 1];
        ++first[size_t(l.q) + 1];
    }
    for (size_t i = 0; i < nn; ++i) first[i + 1] += first[i];
    std::vector<int> src(first[nn]);
    std::vector<double> fac(first[nn]);
    {
        std::vector<size_t> at(first.begin(), first.end() - 1);
        for (const Link& l : links) {
            src[at[size_t(l.p)]] = l.q;
            fac[at[size_t(l.p)]++] = l.s / nodes[size_t(l.p)].g.area;
            src[at[size_t(l.q)]] = l.p;
            fac[at[size_t(l.q)]++] = l.s / nodes[size_t(l.q)].g.area;
        }
    }
    links.clear();
    links.shrink_to_fit();

    // ---- solve: Jacobi sweeps of gather, push and pull -----------------------------------------
    std::vector<double> B(nn * nb, 0), H(nn * nb, 0);
    // The exitances the gather reads, in single precision: the gather streams them once per
    // link (48 bands), and halving those bytes speeds it up; their rounding (6e-8 relative)
    // is far below any residual asked for, and H and B are summed in double.
    std::vector<float> Bf(nn * nb, 0.f);
    std::vector<double> diff(roots.size()), norm(roots.size());
    // Pushes the irradiance gathered above node n (acc) down to its leaves, sets the leaves'
    // B' = rho (E + irradiance) and pulls the area means up; sums |B' - B|^2 and |B'|^2 by area.
    auto push_pull = [&](auto&& self, int n, const double* acc, double& d2, double& b2) -> void {
        const HierNode& N = nodes[size_t(n)];
        double here[64];
        const double* h = &H[size_t(n) * nb];
        for (size_t k = 0; k < nb; ++k) here[k] = acc[k] + h[k];
        double* b = &B[size_t(n) * nb];
        if (N.child < 0) {
            const double* r = &rho[size_t(N.unknown) * nb];
            const double* e = &E[size_t(N.unknown) * nb];
            for (size_t k = 0; k < nb; ++k) {
                const double v = r[k] * (e[k] + here[k]);
                d2 += N.g.area * sqr(v - b[k]);
                b2 += N.g.area * sqr(v);
                b[k] = v;
            }
            return;
        }
        for (int c = 0; c < 4; ++c) self(self, N.child + c, here, d2, b2);
        for (size_t k = 0; k < nb; ++k) {
            double s = 0;
            for (int c = 0; c < 4; ++c)
                s += nodes[size_t(N.child + c)].g.area * B[size_t(N.child + c) * nb + k];
            b[k] = N.g.area > 0 ? s / N.g.area : 0;
        }
    };
    const auto t_sweeps = std::chrono::steady_clock::now();
    const double tol = std::max(prm.residual, 1e-14);
    for (int sweep = 0; sweep < prm.max_sweeps; ++sweep) {
        arena.execute([&] {
            // Gather (the first sweep: from B = 0, so B' = rho E).
            tbb::parallel_for(tbb::blocked_range<size_t>(0, nn, 64), [&](const auto& rg) {
                for (size_t n = rg.begin(); n < rg.end(); ++n) {
                    double* h = &H[n * nb];
                    std::fill(h, h + nb, 0.0);
                    for (size_t e = first[n]; e < first[n + 1]; ++e) {
                        const float* b = &Bf[size_t(src[e]) * nb];
                        const double f = fac[e];
                        for (size_t k = 0; k < nb; ++k) h[k] += f * double(b[k]);
                    }
                }
            });
            tbb::parallel_for(size_t(0), roots.size(), [&](size_t i) {
                const double zero[64] = {};
                double d2 = 0, b2 = 0;
                push_pull(push_pull, roots[i], zero, d2, b2);
                diff[i] = d2;
                norm[i] = b2;
            });
        });
        double d2 = 0, b2 = 0;
        for (size_t i = 0; i < roots.size(); ++i) {
            d2 += diff[i];
            b2 += norm[i];
        }
        for (size_t i = 0; i < nn * nb; ++i) Bf[i] = float(B[i]);
        st.sweeps = sweep + 1;
        st.residual = b2 > 0 ? std::sqrt(d2 / b2) : 0;
        if (sweep > 0 && st.residual <= tol) break;
    }

    st.seconds_sweeps =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t_sweeps).count();
    std::vector<double> out(nu * nb, 0);
    for (size_t i = 0; i < nn; ++i) {
        const HierNode& n = nodes[i];
        if (n.child >= 0 || n.unknown < 0) continue;
        for (size_t k = 0; k < nb; ++k) out[size_t(n.unknown) * nb + k] = B[i * nb + k];
    }
    return out;
}

}  // namespace sr::radiosity
