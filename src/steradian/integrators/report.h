#pragma once
/// A lighting designer's report of a measurement (`steradian measure SCENE --report
/// OUT.html`): one self-contained HTML page (inline CSS and SVG, no script, no external
/// resource) with
///   - the method and its accuracy (target and achieved relative standard errors, CPU time);
///   - each photometric luminaire of the scene: its file's data (manufacturer keywords,
///     format, luminous opening, lamps, flux, efficacy), where it is and how it is scaled,
///     and a polar plot of its intensity distribution in the C0-C180 and C90-C270 planes;
///   - each grid: E_avg, E_min, E_max, U0 = E_min / E_avg and E_min / E_max, a false-colour
///     plan and an isolux contour plan (v up, u to the right, as seen from above the
///     receiving side when the grid's normal points up);
///   - the point and luminance meters' readings with their standard errors.
/// The building blocks (contouring, nice levels, the polar plot) are exposed for tests.
#include <string>
#include <vector>

#include "steradian/integrators/measure.h"

namespace sr {

class Scene;
struct PhotometricData;

struct ReportOptions {
    std::string scene_path;  ///< shown in the title
    std::string title;       ///< empty: "Lighting report: <scene file name>"
};

/// The whole HTML page.
std::string measure_report_html(const Scene& scene, const MeasureResult& result,
                                const ReportOptions& options);

/// A straight piece of a contour line, in the grid's index coordinates: value k of a
/// row-major nx x ny lattice (values[j * nx + i]) sits at (i, j).
struct ContourSegment {
    double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
};
/// The contour of `level` through the lattice by marching squares, with linear interpolation
/// along cell edges (so a field linear in (i, j) gives segments lying exactly on its level
/// line); a saddle cell is resolved by the mean of its four corners. Values equal to the
/// level count as above it. Non-finite values leave their cells out.
std::vector<ContourSegment> contour_segments(const std::vector<double>& values, int nx, int ny,
                                             double level);

/// Contour levels for values in [lo, hi]: the multiples of one step in {1, 2, 2.5, 5} x 10^k
/// strictly inside (lo, hi), the smallest such step giving at most `max_levels` levels.
/// Empty when hi <= lo or either is not finite.
std::vector<double> contour_levels(double lo, double hi, int max_levels);

/// The intensity distribution of a photometric file as an SVG polar diagram (the
/// conventional one: nadir down, C0 to the right and C180 to the left in a solid line,
/// C90 right and C270 left dashed), in cd/klm of lamp flux for relative photometry and cd
/// for absolute photometry. `size` is the square's side in pixels.
std::string polar_plot_svg(const PhotometricData& data, int size = 320);

/// The radius scale of polar_plot_svg: its outer circle's value (a nice number at or above
/// the largest plotted intensity) and the unit ("cd/klm" or "cd"), and the factor from the
/// file's candela to that unit.
struct PolarScale {
    double outer = 1, factor = 1;
    std::string unit;
};
PolarScale polar_plot_scale(const PhotometricData& data);

/// Escapes &, <, >, " and ' for HTML text and attributes.
std::string html_escape(const std::string& s);

}  // namespace sr
