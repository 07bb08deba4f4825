#include "steradian/integrators/report.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>

#include <fmt/format.h>

#include "steradian/film/falsecolor.h"
#include "steradian/lights/photometric/photometric.h"
#include "steradian/scene/scene.h"
#include "steradian/spectrum/spectrum.h"

namespace sr {

std::string html_escape(const std::string& s) {
    std::string out;
    out.reserve(s.size());
    for (char c : s) {
        switch (c) {
            case '&': out += "&amp;"; break;
            case '<': out += "&lt;"; break;
            case '>': out += "&gt;"; break;
            case '"': out += "&quot;"; break;
            case '\'': out += "&#39;"; break;
            default: out += c;
        }
    }
    return out;
}

namespace {

/// The smallest {1, 2, 2.5, 5} x 10^k at or above x (x > 0).
double nice_ceil(double x) {
    if (!(x > 0) || !std::isfinite(x)) return 1;
    double p = std::pow(10.0, std::floor(std::log10(x)));
    for (double m : {1.0, 2.0, 2.5, 5.0, 10.0})
        if (m * p >= x * (1 - 1e-12)) return m * p;
    return 10 * p;
}

std::string num(double v) {
    if (!std::isfinite(v)) return "&mdash;";
    return fmt::format("{:.4g}", v);
}

std::string rgb_hex(Rgb c) {
    auto b = [](Float v) { return int(std::lround(std::clamp(double(v), 0.0, 1.0) * 255)); };
    return fmt::format("#{:02x}{:02x}{:02x}", b(c.r), b(c.g), b(c.b));
}

/// Luminaires of the same file, form and multiplier, listed once with their placements.
struct LuminaireGroup {
    PhotometricLuminaire first;
    std::vector<PhotometricLuminaire> members;
};

std::vector<LuminaireGroup> group_luminaires(const std::vector<PhotometricLuminaire>& lums) {
    std::vector<LuminaireGroup> groups;
    for (const PhotometricLuminaire& l : lums) {
        auto same = [&](const LuminaireGroup& g) {
            const PhotometricData& a = *g.first.profile->data;
            const PhotometricData& b = *l.profile->data;
            return (&a == &b || (a.source == b.source && a.candela == b.candela)) &&
                   g.first.opening == l.opening &&
                   std::abs(g.first.multiplier - l.multiplier) <= 1e-6 * std::abs(l.multiplier);
        };
        auto it = std::find_if(groups.begin(), groups.end(), same);
        if (it == groups.end()) {
            groups.push_back({l, {}});
            it = groups.end() - 1;
        }
        it->members.push_back(l);
    }
    return groups;
}

std::string keyword(const PhotometricData& d, std::initializer_list<const char*> keys) {
    for (const char* k : keys) {
        auto it = d.keywords.find(k);
        if (it != d.keywords.end() && !it->second.empty()) return it->second;
    }
    return "";
}

/// A table row; both cells are HTML (callers escape what comes from files or the scene).
void row(std::string& h, const std::string& name_html, const std::string& value_html) {
    h += fmt::format("<tr><th>{}</th><td>{}</td></tr>\n", name_html, value_html);
}

std::string luminaire_section(const LuminaireGroup& grp, size_t index) {
    const PhotometricLuminaire& l = grp.first;
    const PhotometricData& d = *l.profile->data;
    std::string h;
    std::string title = keyword(d, {"LUMINAIRE", "LUMCAT"});
    const std::string file = std::filesystem::path(d.source).filename().string();
    h += fmt::format("<section class=\"lum\"><h3>Luminaire {}: {}</h3>\n<div class=\"pair\">\n",
                     index + 1, html_escape(title.empty() ? file : title));
    h += "<table class=\"kv\">\n";
    row(h, "File", html_escape(file));
    row(h, "Format", html_escape(d.version.empty() ? std::string(d.format == PhotometricFormat::Ies
                                                                    ? "IES LM-63" : "EULUMDAT")
                                                   : d.version));
    const std::string manufacturer = keyword(d, {"MANUFAC", "COMPANY"});
    if (!manufacturer.empty()) row(h, "Manufacturer", html_escape(manufacturer));
    const std::string cat = keyword(d, {"LUMCAT"});
    if (!cat.empty()) row(h, "Catalogue number", html_escape(cat));
    const std::string lamp = keyword(d, {"LAMP", "LAMPCAT"});
    if (!lamp.empty()) row(h, "Lamp", html_escape(lamp));
    const std::string test = keyword(d, {"TEST", "REPORT"});
    if (!test.empty()) row(h, "Test report", html_escape(test));
    row(h, "Photometric type", fmt::format("Type {}", to_string(d.type)));
    std::string opening = to_string(d.shape);
    if (d.shape != LuminousShape::Point)
        opening += fmt::format(" (width {} m, length {} m, height {} m)", num(d.width),
                               num(d.length), num(d.height));
    row(h, "Luminous opening", html_escape(opening));
    const double flux = d.total_flux();
    const double nominal = d.nominal_flux();
    if (nominal > 0)
        row(h, "Lamp flux (relative photometry)",
            fmt::format("{} &times; {} lm", d.num_lamps, num(d.lamp_lumens)));
    else
        row(h, "Photometry", "absolute");
    row(h, "Luminaire flux (file)", num(flux) + " lm");
    if (nominal > 0) row(h, "Light output ratio", fmt::format("{:.1f} %", 100 * flux / nominal));
    row(h, "Maximum intensity (file)", num(d.max_intensity()) + " cd");
    if (d.input_watts > 0) {
        row(h, "Input power", num(d.input_watts) + " W");
        row(h, "Luminaire efficacy", num(flux / d.input_watts) + " lm/W");
    }
    if (d.ballast_factor != 1) row(h, "Ballast factor (applied)", num(d.ballast_factor));
    row(h, "Form in the scene", l.opening ? "luminous opening (emitting surface)"
                                          : "point source (far-field distribution)");
    row(h, "Multiplier in the scene", num(l.multiplier));
    row(h, "Flux in the scene", num(l.multiplier * flux) + " lm per luminaire");
    row(h, "Number in the scene", std::to_string(grp.members.size()));
    std::string places;
    for (const PhotometricLuminaire& m : grp.members) {
        if (!places.empty()) places += "<br/>";
        const Point3 c = m.centre();
        const Vec3 n = m.nadir();
        places += fmt::format("({}, {}, {}) m, nadir towards ({}, {}, {})", num(c.x), num(c.y),
                              num(c.z), num(n.x), num(n.y), num(n.z));
    }
    row(h, "Positions", places);
    h += "</table>\n";
    h += "<figure>" + polar_plot_svg(d) + "<figcaption>Intensity distribution (" +
         polar_plot_scale(d).unit + "): C0&ndash;C180 solid, C90&ndash;C270 dashed; nadir "
         "down.</figcaption></figure>\n";
    h += "</div></section>\n";
    return h;
}

/// The scale shared by a grid's false-colour plan and its legend.
struct GridScale {
    FalseColorRange range;
    std::vector<double> ticks;
};

GridScale grid_scale(const MeterReading& rd) {
    Image v;
    v.width = int(rd.values.size());
    v.height = 1;
    v.channels = 1;
    v.data.assign(rd.values.begin(), rd.values.end());
    FalseColorOptions fo;
    fo.log_scale = false;
    GridScale s;
    s.range = false_color_range(v, fo);
    s.ticks = false_color_ticks(s.range.min, s.range.max, false, 300, 28);
    return s;
}

/// Plan geometry of a grid: the cells drawn as w x h pixels, v up.
struct Plan {
    int nu = 0, nv = 0;
    double cw = 0, ch = 0;  ///< pixels per cell
    double x0 = 50, y0 = 20;
    double width() const { return nu * cw; }
    double height() const { return nv * ch; }
    double x(double i) const { return x0 + (i + 0.5) * cw; }     // cell-centre index -> px
    double y(double j) const { return y0 + (nv - 0.5 - j) * ch; }
};

Plan plan_for(const Meter& m) {
    Plan p;
    p.nu = m.nu;
    p.nv = m.nv;
    const double lu = length(m.cell_u) * m.nu, lv = length(m.cell_v) * m.nv;
    const double box = 360;
    double sx = box / std::max(lu, 1e-9), sy = box / std::max(lv, 1e-9);
    double s = std::min(sx, sy);
    if (!(s > 0) || !std::isfinite(s)) s = 1;
    p.cw = std::max(lu * s / m.nu, 1e-3);
    p.ch = std::max(lv * s / m.nv, 1e-3);
    return p;
}

std::string axes_svg(const Plan& p, const Meter& m) {
    const double lu = length(m.cell_u) * m.nu, lv = length(m.cell_v) * m.nv;
    std::string s = fmt::format(
        "<rect x=\"{:.2f}\" y=\"{:.2f}\" width=\"{:.2f}\" height=\"{:.2f}\" fill=\"none\" "
        "stroke=\"#333\"/>\n",
        p.x0, p.y0, p.width(), p.height());
    s += fmt::format("<text x=\"{:.2f}\" y=\"{:.2f}\" class=\"ax\" text-anchor=\"middle\">u: "
                     "{} m</text>\n",
                     p.x0 + p.width() / 2, p.y0 + p.height() + 16, num(lu));
    s += fmt::format("<text x=\"{:.2f}\" y=\"{:.2f}\" class=\"ax\" text-anchor=\"middle\" "
                     "transform=\"rotate(-90 {:.2f} {:.2f})\">v: {} m</text>\n",
                     p.x0 - 10, p.y0 + p.height() / 2, p.x0 - 10, p.y0 + p.height() / 2,
                     num(lv));
    return s;
}

std::string false_colour_svg(const MeterReading& rd, const GridScale& sc) {
    const Meter& m = rd.meter;
    Plan p = plan_for(m);
    const double legend_x = p.x0 + p.width() + 20;
    const double w = legend_x + 90, h = p.y0 + p.height() + 30;
    std::string s = fmt::format(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{:.0f}\" height=\"{:.0f}\" "
        "viewBox=\"0 0 {:.0f} {:.0f}\" role=\"img\"><title>False-colour plan of {}</title>\n",
        w, h, w, h, html_escape(m.name));
    s += "<g shape-rendering=\"crispEdges\">\n";
    for (int j = 0; j < m.nv; ++j)
        for (int i = 0; i < m.nu; ++i) {
            const double v = rd.values[size_t(j) * m.nu + i];
            const double t = false_color_position(v, sc.range, false);
            const Rgb c = std::isnan(t) ? false_color_nan_srgb() : false_color_palette_srgb(t);
            s += fmt::format("<rect x=\"{:.2f}\" y=\"{:.2f}\" width=\"{:.2f}\" height=\"{:.2f}\" "
                             "fill=\"{}\"/>\n",
                             p.x0 + i * p.cw, p.y0 + (m.nv - 1 - j) * p.ch, p.cw + 0.02,
                             p.ch + 0.02, rgb_hex(c));
        }
    s += "</g>\n" + axes_svg(p, m);
    // Legend: a vertical bar of 64 steps, max at the top.
    const double bar_top = p.y0, bar_h = std::max(p.height(), 120.0), bar_w = 16;
    for (int k = 0; k < 64; ++k) {
        const double t0 = 1 - (k + 1) / 64.0;
        s += fmt::format("<rect x=\"{:.2f}\" y=\"{:.2f}\" width=\"{:.2f}\" height=\"{:.3f}\" "
                         "fill=\"{}\"/>\n",
                         legend_x, bar_top + k * bar_h / 64, bar_w, bar_h / 64 + 0.05,
                         rgb_hex(false_color_palette_srgb(t0 + 0.5 / 64)));
    }
    for (double t : sc.ticks) {
        const double f = false_color_position(t, sc.range, false);
        const double y = bar_top + (1 - f) * bar_h;
        s += fmt::format("<line x1=\"{:.2f}\" y1=\"{:.2f}\" x2=\"{:.2f}\" y2=\"{:.2f}\" "
                         "stroke=\"#333\"/><text x=\"{:.2f}\" y=\"{:.2f}\" class=\"ax\">{}</text>\n",
                         legend_x + bar_w, y, legend_x + bar_w + 5, y, legend_x + bar_w + 8,
                         y + 4, html_escape(format_tick(t)));
    }
    s += fmt::format("<text x=\"{:.2f}\" y=\"{:.2f}\" class=\"ax\">{}</text>\n", legend_x,
                     bar_top + bar_h + 16, html_escape(m.unit()));
    s += "</svg>";
    return s;
}

std::string isolux_svg(const MeterReading& rd, const GridScale& sc) {
    const Meter& m = rd.meter;
    Plan p = plan_for(m);
    const double w = p.x0 + p.width() + 20, h = p.y0 + p.height() + 30;
    std::string s = fmt::format(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{:.0f}\" height=\"{:.0f}\" "
        "viewBox=\"0 0 {:.0f} {:.0f}\" role=\"img\"><title>Isolux plan of {}</title>\n",
        w, h, w, h, html_escape(m.name));
    s += fmt::format("<rect x=\"{:.2f}\" y=\"{:.2f}\" width=\"{:.2f}\" height=\"{:.2f}\" "
                     "fill=\"#fafafa\"/>\n",
                     p.x0, p.y0, p.width(), p.height());
    double lo = rd.min, hi = rd.max;
    std::vector<double> levels = contour_levels(lo, hi, 10);
    std::string labels;
    for (double level : levels) {
        const double t = false_color_position(level, sc.range, false);
        const std::string colour = rgb_hex(false_color_palette_srgb(std::isnan(t) ? 0 : t) * Float(0.8));
        std::vector<ContourSegment> segs = contour_segments(rd.values, m.nu, m.nv, level);
        if (segs.empty()) continue;
        std::string d;
        size_t longest = 0;
        double longest_len = -1;
        for (size_t k = 0; k < segs.size(); ++k) {
            const ContourSegment& g = segs[k];
            d += fmt::format("M{:.2f} {:.2f}L{:.2f} {:.2f}", p.x(g.x0), p.y(g.y0), p.x(g.x1),
                             p.y(g.y1));
            const double len = std::hypot((g.x1 - g.x0) * p.cw, (g.y1 - g.y0) * p.ch);
            // Label the contour where it is drawn across the middle of the plan, roughly.
            const double cx = (g.x0 + g.x1) / 2 - (m.nu - 1) / 2.0;
            const double cy = (g.y0 + g.y1) / 2 - (m.nv - 1) / 2.0;
            const double score = len - 0.02 * std::hypot(cx * p.cw, cy * p.ch);
            if (score > longest_len) longest_len = score, longest = k;
        }
        s += fmt::format("<path d=\"{}\" fill=\"none\" stroke=\"{}\" stroke-width=\"1.5\"/>\n", d,
                         colour);
        const ContourSegment& g = segs[longest];
        labels += fmt::format("<text x=\"{:.2f}\" y=\"{:.2f}\" class=\"cl\" "
                              "text-anchor=\"middle\">{}</text>\n",
                              p.x((g.x0 + g.x1) / 2), p.y((g.y0 + g.y1) / 2) + 4,
                              html_escape(format_tick(level)));
    }
    s += labels + axes_svg(p, m) + "</svg>";
    return s;
}

double rel(double se, double v) { return v != 0 ? std::abs(se / v) : 0; }

}  // namespace

std::vector<double> contour_levels(double lo, double hi, int max_levels) {
    std::vector<double> out;
    if (!std::isfinite(lo) || !std::isfinite(hi) || !(hi > lo) || max_levels < 1) return out;
    const double span = hi - lo;
    double p = std::pow(10.0, std::floor(std::log10(span / max_levels)) - 1);
    for (int guard = 0; guard < 64; ++guard, p *= 10) {
        for (double mult : {1.0, 2.0, 2.5, 5.0}) {
            const double step = mult * p;
            const double first = std::floor(lo / step) + 1, last = std::ceil(hi / step) - 1;
            if (last - first + 1 <= max_levels) {
                for (double k = first; k <= last; ++k) out.push_back(k * step);
                return out;
            }
        }
    }
    return out;
}

std::vector<ContourSegment> contour_segments(const std::vector<double>& values, int nx, int ny,
                                             double level) {
    std::vector<ContourSegment> out;
    if (nx < 2 || ny < 2 || values.size() < size_t(nx) * size_t(ny)) return out;
    auto at = [&](int i, int j) { return values[size_t(j) * nx + i]; };
    for (int j = 0; j + 1 < ny; ++j)
        for (int i = 0; i + 1 < nx; ++i) {
            // Corners counterclockwise from (i, j): a, b = (i+1, j), c = (i+1, j+1), d.
            const double v[4] = {at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)};
            const double px[4] = {double(i), double(i + 1), double(i + 1), double(i)};
            const double py[4] = {double(j), double(j), double(j + 1), double(j + 1)};
            if (!std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2]) ||
                !std::isfinite(v[3]))
                continue;
            bool in[4];
            for (int k = 0; k < 4; ++k) in[k] = v[k] >= level;
            // Edge e runs from corner e to corner (e + 1) % 4.
            auto cross = [&](int e, double& x, double& y) {
                const int a = e, b = (e + 1) % 4;
                const double t = (level - v[a]) / (v[b] - v[a]);
                x = px[a] + t * (px[b] - px[a]);
                y = py[a] + t * (py[b] - py[a]);
            };
            int edges[4], n = 0;
            for (int e = 0; e < 4; ++e)
                if (in[e] != in[(e + 1) % 4]) edges[n++] = e;
            auto emit = [&](int e0, int e1) {
                ContourSegment g;
                cross(e0, g.x0, g.y0);
                cross(e1, g.x1, g.y1);
                out.push_back(g);
            };
            if (n == 2) {
                emit(edges[0], edges[1]);
            } else if (n == 4) {
                // A saddle: corners a and c on one side, b and d on the other. If the centre
                // is on a's side, a and c join through the middle and the lines cut off b
                // (edges 0, 1) and d (edges 2, 3); else they cut off a (3, 0) and c (1, 2).
                const bool centre_in = (v[0] + v[1] + v[2] + v[3]) / 4 >= level;
                if (centre_in == in[0]) {
                    emit(0, 1);
                    emit(2, 3);
                } else {
                    emit(3, 0);
                    emit(1, 2);
                }
            }
        }
    return out;
}

PolarScale polar_plot_scale(const PhotometricData& d) {
    PolarScale s;
    const double nominal = d.nominal_flux();
    s.factor = nominal > 0 ? 1000 / nominal : 1;
    s.unit = nominal > 0 ? "cd/klm" : "cd";
    double peak = 0;
    for (double c : {0.0, 90.0, 180.0, 270.0})
        for (int g = 0; g <= 180; ++g) peak = std::max(peak, d.intensity(g, c) * s.factor);
    s.outer = nice_ceil(peak > 0 ? peak : 1);
    return s;
}

std::string polar_plot_svg(const PhotometricData& d, int size) {
    const PolarScale sc = polar_plot_scale(d);
    const double cx = size / 2.0, cy = size / 2.0, R = size / 2.0 - 24;
    auto pt = [&](double gamma_deg, double value, bool right) {
        const double g = gamma_deg * kPi / 180, r = R * value / sc.outer;
        return std::pair{cx + (right ? 1 : -1) * r * std::sin(g), cy + r * std::cos(g)};
    };
    std::string s = fmt::format(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{0}\" height=\"{0}\" "
        "viewBox=\"0 0 {0} {0}\" role=\"img\"><title>Polar intensity diagram</title>\n",
        size);
    // Rings at quarters of the outer value, spokes every 30 degrees.
    for (int k = 1; k <= 4; ++k) {
        const double r = R * k / 4;
        s += fmt::format("<circle cx=\"{:.2f}\" cy=\"{:.2f}\" r=\"{:.2f}\" fill=\"none\" "
                         "stroke=\"#ccc\"/>\n",
                         cx, cy, r);
        s += fmt::format("<text x=\"{:.2f}\" y=\"{:.2f}\" class=\"ax\">{}</text>\n", cx + 3,
                         cy - r + 11, html_escape(format_tick(sc.outer * k / 4)));
    }
    for (int a = 0; a < 360; a += 30) {
        const double t = a * kPi / 180;
        s += fmt::format("<line x1=\"{:.2f}\" y1=\"{:.2f}\" x2=\"{:.2f}\" y2=\"{:.2f}\" "
                         "stroke=\"#ddd\"/>\n",
                         cx, cy, cx + R * std::sin(t), cy + R * std::cos(t));
        const int label = a <= 180 ? a : 360 - a;
        s += fmt::format("<text x=\"{:.2f}\" y=\"{:.2f}\" class=\"ax\" text-anchor=\"middle\">"
                         "{}&#176;</text>\n",
                         cx + (R + 12) * std::sin(t), cy + (R + 12) * std::cos(t) + 4, label);
    }
    // One closed-over-the-poles line per plane pair: from gamma = 180 on the left plane down
    // to the nadir and up to 180 on the right plane.
    auto plane_path = [&](double c_right, double c_left) {
        std::string p;
        for (int g = 180; g >= 0; --g) {
            auto [x, y] = pt(g, d.intensity(g, c_left) * sc.factor, false);
            p += fmt::format("{}{:.2f} {:.2f}", p.empty() ? "M" : "L", x, y);
        }
        for (int g = 1; g <= 180; ++g) {
            auto [x, y] = pt(g, d.intensity(g, c_right) * sc.factor, true);
            p += fmt::format("L{:.2f} {:.2f}", x, y);
        }
        return p;
    };
    s += "<path d=\"" + plane_path(0, 180) +
         "\" fill=\"none\" stroke=\"#c0392b\" stroke-width=\"2\"/>\n";
    s += "<path d=\"" + plane_path(90, 270) +
         "\" fill=\"none\" stroke=\"#2457a6\" stroke-width=\"2\" stroke-dasharray=\"6 4\"/>\n";
    s += fmt::format("<text x=\"4\" y=\"14\" class=\"ax\">{}</text>\n", html_escape(sc.unit));
    s += fmt::format("<text x=\"{}\" y=\"14\" class=\"ax\" text-anchor=\"end\" fill=\"#c0392b\">"
                     "C0&#8211;C180</text>\n",
                     size - 4);
    s += fmt::format("<text x=\"{}\" y=\"28\" class=\"ax\" text-anchor=\"end\" fill=\"#2457a6\">"
                     "C90&#8211;C270</text>\n",
                     size - 4);
    s += "</svg>";
    return s;
}

std::string measure_report_html(const Scene& scene, const MeasureResult& r,
                                const ReportOptions& o) {
    const std::string file = std::filesystem::path(o.scene_path).filename().string();
    const std::string title = o.title.empty() ? "Lighting report: " + file : o.title;
    std::string h;
    h += "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"/>\n<title>" +
         html_escape(title) + "</title>\n";
    h += R"(<style>
body{font-family:"DejaVu Sans",Helvetica,Arial,sans-serif;margin:24px;color:#222;max-width:1100px}
h1{font-size:22px}h2{font-size:18px;border-bottom:1px solid #ccc;padding-bottom:4px;margin-top:32px}
h3{font-size:15px;margin-bottom:6px}
table{border-collapse:collapse;font-size:13px;margin:8px 0}
td,th{border:1px solid #ccc;padding:3px 8px;text-align:right}
th{background:#f2f2f2}
table.kv th{text-align:left;font-weight:normal;background:#f7f7f7}
table.kv td{text-align:left}
.pair{display:flex;flex-wrap:wrap;gap:24px;align-items:flex-start}
.pair>*{flex:0 0 auto}
figure{margin:0}figcaption{font-size:12px;color:#555;max-width:420px}
svg .ax{font-size:11px;fill:#333}svg .cl{font-size:11px;fill:#111;paint-order:stroke;stroke:#fff;stroke-width:3px}
.note{font-size:12px;color:#555}
.warn{color:#a61b1b}
</style></head><body>
)";
    h += "<h1>" + html_escape(title) + "</h1>\n";
    h += "<p class=\"note\">Scene <code>" + html_escape(o.scene_path) +
         "</code>. Computed by steradian.</p>\n";

    // ---- method and accuracy
    double worst = 0;
    size_t values = 0, unconverged = 0;
    for (const MeterReading& rd : r.readings)
        for (size_t k = 0; k < rd.values.size(); ++k) {
            ++values;
            worst = std::max(worst, rel(rd.stderrs[k], rd.values[k]));
            if (!rd.converged[k]) ++unconverged;
        }
    h += "<h2>Method and accuracy</h2>\n<table class=\"kv\">\n";
    row(h, "Method",
        r.method == "radiosity"
            ? "radiosity (direct light from every light per meter point, by closed forms and "
              "adaptive quadrature where the meter's estimator says \"deterministic\"; "
              "indirect light by gather rays reading the radiosity solution)"
        : r.method == "light"
            ? "light tracing for the cell-averaged grids (particles from the lights; a cell's "
              "illuminance is the flux that crosses it over its area), path tracing for the "
              "other meters"
            : "path tracing (Monte Carlo, light sampling and BSDF sampling combined by multiple "
              "importance sampling)");
    for (const auto& [k, v] : r.method_figures) row(h, html_escape(r.method + ": " + k), num(v));
    row(h, "Target relative standard error", fmt::format("{:.3g} %", 100 * r.rel_error_target));
    row(h, "Largest relative standard error reached", fmt::format("{:.3g} %", 100 * worst));
    row(h, "Values", fmt::format("{} ({} not at the target{})", values, unconverged,
                                 r.time_limited ? ": time budget" : ""));
    row(h, "Uncertainty",
        "each value's standard error is the spread of independent randomised replicas "
        "(randomised quasi-Monte Carlo); a value &plusmn; 2 standard errors covers the exact "
        "answer of the scene as modelled about 95 % of the time");
    row(h, "CPU time", fmt::format("{:.3f} s ({:.3f} s wall)", r.cpu_seconds, r.wall_seconds));
    row(h, "Paths traced", fmt::format("{}", r.paths));
    if (r.nonfinite > 0)
        row(h, "Non-finite samples (zeroed)",
            fmt::format("<span class=\"warn\">{}</span>", r.nonfinite));
    h += "</table>\n";

    // ---- luminaires
    std::vector<PhotometricLuminaire> lums = photometric_luminaires(scene);
    h += "<h2>Luminaires</h2>\n";
    if (lums.empty())
        h += "<p>The scene has no luminaire from a photometric file (IES or EULUMDAT).</p>\n";
    std::vector<LuminaireGroup> groups = group_luminaires(lums);
    for (size_t k = 0; k < groups.size(); ++k) h += luminaire_section(groups[k], k);
    size_t other = scene.lights.size();
    for (const Light& light : scene.lights) {
        if (const auto* g = std::get_if<GoniometricLight>(&light); g && g->profile.data) --other;
        if (const auto* a = std::get_if<DiffuseAreaLight>(&light);
            a && a->goniometric && a->goniometric->profile.data)
            --other;
    }
    if (other > 0)
        h += fmt::format("<p class=\"note\">The scene has {} other light{} (point, spot, area, "
                         "distant, sky or environment lights; area lights count once per "
                         "emitting primitive).</p>\n",
                         other, other == 1 ? "" : "s");

    // ---- grids
    bool any_grid = false;
    for (const MeterReading& rd : r.readings) {
        if (rd.meter.kind != MeterKind::Grid) continue;
        if (!any_grid) h += "<h2>Calculation grids</h2>\n";
        any_grid = true;
        const Meter& m = rd.meter;
        const std::string u = html_escape(m.unit());
        h += "<section class=\"grid\"><h3>" + html_escape(m.name) + " (" + html_escape(m.type) +
             ", " + std::to_string(m.nu) + " &times; " + std::to_string(m.nv) + " points)</h3>\n";
        h += "<table><tr><th>E<sub>avg</sub></th><th>E<sub>min</sub></th><th>E<sub>max</sub>"
             "</th><th>U<sub>0</sub> = E<sub>min</sub>/E<sub>avg</sub></th><th>E<sub>min</sub>/"
             "E<sub>max</sub></th><th>Unit</th></tr>\n";
        h += fmt::format("<tr><td>{} &plusmn; {}</td><td>{}</td><td>{}</td><td>{:.3f}</td>"
                         "<td>{:.3f}</td><td>{}</td></tr></table>\n",
                         num(rd.avg), num(rd.avg_stderr), num(rd.min), num(rd.max),
                         rd.uniformity, rd.max > 0 ? rd.min / rd.max : 0.0, u);
        const double c = length(m.cell_u), cv = length(m.cell_v);
        h += fmt::format("<p class=\"note\">Cells {} m &times; {} m; {}; component: {}. "
                         "E<sub>avg</sub>'s standard error combines the points'.</p>\n",
                         num(c), num(cv),
                         m.cell_average ? "each value is its cell's mean"
                                        : "each value is at its cell's centre",
                         m.component == MeterComponent::All      ? "all light"
                         : m.component == MeterComponent::Direct ? "direct light only"
                                                                 : "indirect light only");
        GridScale sc = grid_scale(rd);
        h += "<div class=\"pair\"><figure>" + false_colour_svg(rd, sc) +
             "<figcaption>False colour (" + u + "), seen from the receiving side; v up.</figcaption>"
             "</figure><figure>" + isolux_svg(rd, sc) + "<figcaption>Isolines (" + u +
             ").</figcaption></figure></div>\n";
        // The values themselves, v down the rows as in the plans (a compact table up to 32 x 32).
        if (m.nu <= 32 && m.nv <= 32) {
            h += "<details><summary>Values (" + u + ")</summary><table class=\"vals\">\n";
            for (int j = m.nv - 1; j >= 0; --j) {
                h += "<tr>";
                for (int i = 0; i < m.nu; ++i)
                    h += "<td>" + num(rd.values[size_t(j) * m.nu + i]) + "</td>";
                h += "</tr>\n";
            }
            h += "</table></details>\n";
        }
        h += "</section>\n";
    }

    // ---- glare
    bool any_glare = false;
    for (const MeterReading& rd : r.readings) {
        if (!rd.meter.glare) continue;
        if (!any_glare)
            h += "<h2>Discomfort glare (UGR, CIE 117:1995)</h2>\n<p class=\"note\">UGR = 8 "
                 "log<sub>10</sub>(0.25 / L<sub>b</sub> &Sigma; L&sup2;&omega; / p&sup2;): "
                 "L<sub>b</sub> = E<sub>ind</sub> / &pi; from the indirect illuminance at the "
                 "eye, L and &omega; of each luminaire's luminous opening seen from the eye, p "
                 "Guth's position index (Levin's form). CIE 117 holds for 10 &le; UGR &le; 30 "
                 "and luminaires of 0.0003 to 0.1 sr; its position index covers luminaires "
                 "above the line of sight.</p>\n";
        any_glare = true;
        for (size_t k = 0; k < rd.glare.size(); ++k) {
            const GlareReading& g = rd.glare[k];
            const Point3 e = rd.meter.points[k];
            const Vec3 v = rd.meter.directions[k];
            h += fmt::format("<h3>{}: eye at ({}, {}, {}) looking towards ({}, {}, {})</h3>\n",
                             html_escape(rd.meter.name), num(e.x), num(e.y), num(e.z), num(v.x),
                             num(v.y), num(v.z));
            h += "<table class=\"kv\">\n";
            row(h, "UGR", g.defined ? fmt::format("{:.1f} &plusmn; {:.2g}", g.ugr, g.ugr_stderr)
                                    : std::string("undefined"));
            row(h, "Background luminance L<sub>b</sub>",
                num(g.background_luminance) + " cd/m&sup2;");
            row(h, "Indirect illuminance at the eye",
                fmt::format("{} &plusmn; {} lx", num(g.indirect_illuminance),
                            num(g.indirect_stderr)));
            row(h, "Within CIE 117's validity", g.in_range ? "yes" : "no");
            if (!g.note.empty()) row(h, "Note", html_escape(g.note));
            h += "</table>\n<table><tr><th>Luminaire</th><th>Position</th><th>r (m)</th>"
                 "<th>I (cd)</th><th>A (m&sup2;)</th><th>&omega; (sr)</th><th>L (cd/m&sup2;)</th>"
                 "<th>p</th><th>L&sup2;&omega;/p&sup2;</th><th>Remark</th></tr>\n";
            for (const GlareSource& s : g.sources)
                h += fmt::format(
                    "<tr><td>{}</td><td>({}, {}, {})</td><td>{}</td><td>{}</td><td>{}</td>"
                    "<td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>\n",
                    html_escape(s.file), num(s.position.x), num(s.position.y), num(s.position.z),
                    num(s.distance), num(s.intensity), num(s.projected_area),
                    s.counted ? num(s.solid_angle) : "&mdash;",
                    s.counted ? num(s.luminance) : "&mdash;",
                    s.position_index > 0 ? num(s.position_index) : "&mdash;",
                    s.counted ? num(s.term) : "not counted", html_escape(s.note));
            h += "</table>\n";
        }
    }

    // ---- point and luminance meters
    bool any_point = false;
    for (const MeterReading& rd : r.readings) {
        if (rd.meter.kind == MeterKind::Grid || rd.meter.glare) continue;
        if (!any_point)
            h += "<h2>Meters</h2>\n<table><tr><th>Meter</th><th>Type</th><th>Point</th>"
                 "<th>Value</th><th>Standard error</th><th>Unit</th></tr>\n";
        any_point = true;
        for (size_t k = 0; k < rd.values.size(); ++k) {
            const Point3 p = rd.meter.points[k];
            h += fmt::format("<tr><td>{}</td><td>{}</td><td>({}, {}, {})</td><td>{}</td>"
                             "<td>{} ({:.2g} %){}</td><td>{}</td></tr>\n",
                             html_escape(rd.meter.name), html_escape(rd.meter.type), num(p.x),
                             num(p.y), num(p.z), num(rd.values[k]), num(rd.stderrs[k]),
                             100 * rel(rd.stderrs[k], rd.values[k]),
                             rd.converged[k] ? "" : " <span class=\"warn\">not at target</span>",
                             html_escape(rd.meter.unit()));
        }
    }
    if (any_point) h += "</table>\n";
    h += "</body></html>\n";
    return h;
}

}  // namespace sr
