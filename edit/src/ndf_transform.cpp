#include <npf/edit/ndf_transform.h>

#include "tables.h"

#include <npf/core/error.h>
#include <npf/core/number_text.h>
#include <npf/core/vec.h>
#include <npf/shading/npf_equation.h>
#include <npf/shading/table_interpolation.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace npf::edit {

namespace {

const char* const kSource = "ndf transform";

double determinant(const Mat3& a) {
    return a(0, 0) * (a(1, 1) * a(2, 2) - a(1, 2) * a(2, 1)) - a(0, 1) * (a(1, 0) * a(2, 2) - a(1, 2) * a(2, 0)) +
           a(0, 2) * (a(1, 0) * a(2, 1) - a(1, 1) * a(2, 0));
}

Mat3 inverse(const Mat3& a, double det) {
    Mat3 r;
    r(0, 0) = (a(1, 1) * a(2, 2) - a(1, 2) * a(2, 1)) / det;
    r(0, 1) = (a(0, 2) * a(2, 1) - a(0, 1) * a(2, 2)) / det;
    r(0, 2) = (a(0, 1) * a(1, 2) - a(0, 2) * a(1, 1)) / det;
    r(1, 0) = (a(1, 2) * a(2, 0) - a(1, 0) * a(2, 2)) / det;
    r(1, 1) = (a(0, 0) * a(2, 2) - a(0, 2) * a(2, 0)) / det;
    r(1, 2) = (a(0, 2) * a(1, 0) - a(0, 0) * a(1, 2)) / det;
    r(2, 0) = (a(1, 0) * a(2, 1) - a(1, 1) * a(2, 0)) / det;
    r(2, 1) = (a(0, 1) * a(2, 0) - a(0, 0) * a(2, 1)) / det;
    r(2, 2) = (a(0, 0) * a(1, 1) - a(0, 1) * a(1, 0)) / det;
    return r;
}

Mat3 transpose(const Mat3& a) {
    Mat3 r;
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) r(i, j) = a(j, i);
    }
    return r;
}

struct Dir {
    double x, y, z;
};

Dir times(const Mat3& a, const Dir& v) {
    return {a(0, 0) * v.x + a(0, 1) * v.y + a(0, 2) * v.z, a(1, 0) * v.x + a(1, 1) * v.y + a(1, 2) * v.z,
            a(2, 0) * v.x + a(2, 1) * v.y + a(2, 2) * v.z};
}

bool tangent_plane(const Mat3& m) { return m(0, 2) == 0.0 && m(1, 2) == 0.0 && m(2, 0) == 0.0 && m(2, 1) == 0.0; }

// A rotation about the normal (m normalised to m(2, 2) = 1): theta_h, theta_d and phi_d of every
// pair are unchanged by it, so the detail layer, which depends on those alone, stays valid. A
// scaled rotation changes theta_h, and a reflection turns phi_d into -phi_d.
bool rotation_about_normal(const Mat3& m) {
    if (!tangent_plane(m)) return false;
    const double a = m(0, 0), b = m(0, 1), c = m(1, 0), d = m(1, 1);
    const double n1 = a * a + c * c, n2 = b * b + d * d, cross = a * b + c * d;
    return std::fabs(n1 - 1.0) <= 1e-9 && std::fabs(n2 - 1.0) <= 1e-9 && std::fabs(cross) <= 1e-9 && a * d - b * c > 0.0;
}

using table::Bilinear;
using table::bilinear;

// Where a unit direction falls on D's table (NpfModel::prepare's rule) and on G's.
Bilinear d_position(const Dir& h, int d_theta, int d_phi) {
    const double theta = table::polar(h.x, h.y, h.z);
    const table::Lerp row = equation::d_row(equation::u_of_theta_h(theta), d_theta);
    const table::Lerp col = d_phi == 1 ? table::Lerp{} : equation::column(table::azimuth(h.x, h.y), d_phi);
    return bilinear(row, col, d_phi);
}

Bilinear g_position(const Dir& w, int g_theta, int g_phi) {
    const table::Lerp row = equation::g_row(table::polar(w.x, w.y, w.z), g_theta);
    const table::Lerp col = g_phi == 1 ? table::Lerp{} : equation::column(table::azimuth(w.x, w.y), g_phi);
    return bilinear(row, col, g_phi);
}

double at(const double* t, const Bilinear& b) {
    const double v = t[b.index[0]] * b.weight[0] + t[b.index[1]] * b.weight[1] + t[b.index[2]] * b.weight[2] +
                     t[b.index[3]] * b.weight[3];
    return v > 0.0 ? v : 0.0;
}

std::vector<double> first_row_means(const detail::Tables& g, int g_phi) {
    std::vector<double> out(g.channels, 0.0);
    for (std::size_t c = 0; c < g.channels; ++c) {
        double s = 0.0;
        for (int j = 0; j < g_phi; ++j) s += std::max(0.0, g.row(c)[j]);
        out[c] = s / g_phi;
    }
    return out;
}

void check_factor(double v, const char* what) {
    if (!std::isfinite(v) || !(v > 0.0)) {
        throw Error(kSource, std::string(what) + " must be a positive finite number, got " + number_text(v));
    }
}

std::string range_text(const std::vector<double>& v) {
    if (v.empty()) return "-";
    const auto [lo, hi] = std::minmax_element(v.begin(), v.end());
    return *lo == *hi ? number_text(*lo, 6) : number_text(*lo, 6) + ".." + number_text(*hi, 6);
}

// The unit direction at polar angle theta and azimuth phi.
Dir direction(double theta, double phi) {
    return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

// a v / |a v|, with |a v| in `length`.
Dir mapped_unit(const Mat3& a, const Dir& v, double& length) {
    const Dir q = times(a, v);
    length = std::sqrt(q.x * q.x + q.y * q.y + q.z * q.z);
    return {q.x / length, q.y / length, q.z / length};
}

// fn(cell, w) for the centre direction w of every cell of a theta_cells x phi_cells table
// (theta(i) the centre of row i; one column means phi = 0).
template <class Theta, class Fn>
void for_each_cell_centre(int theta_cells, int phi_cells, Theta theta, Fn fn) {
    for (int i = 0; i < theta_cells; ++i) {
        const double t = theta(i, theta_cells);
        for (int j = 0; j < phi_cells; ++j) {
            const double phi = phi_cells == 1 ? 0.0 : equation::phi_centre(j, phi_cells);
            fn(std::size_t(i) * std::size_t(phi_cells) + std::size_t(j), direction(t, phi));
        }
    }
}

detail::Tables zero_tables(std::size_t channels, int theta_cells, int phi_cells) {
    detail::Tables t;
    t.channels = channels;
    t.cells = std::size_t(theta_cells) * std::size_t(phi_cells);
    t.v.assign(channels * t.cells, 0.0);
    return t;
}

// The matrix as applied: checked, scaled to M[2][2] = 1, with its determinant.
struct NormalMatrix {
    Mat3 m;
    double det = 0.0;
};

NormalMatrix normal_matrix(const Mat3& given, const NdfTransformOptions& options) {
    for (double v : given.m) {
        if (!std::isfinite(v)) throw Error(kSource, "the matrix " + matrix_text(given) + " has a non-finite entry");
    }
    if (options.phi_cells < 0 || options.phi_cells > 4096) {
        throw Error(kSource, "phi cells " + std::to_string(options.phi_cells) + " is outside 0..4096");
    }
    if (given(2, 2) == 0.0) {
        throw Error(kSource, "the matrix " + matrix_text(given) + " maps the normal onto the horizon (M[2][2] = 0)");
    }
    // h' = M h / |M h| does not change when M is scaled by a positive number; dividing by M[2][2]
    // also makes the image of the normal point up.
    NormalMatrix n{given, 0.0};
    for (double& v : n.m.m) v /= given(2, 2);
    double norm = 0.0;
    for (double v : n.m.m) norm = std::max(norm, std::fabs(v));
    n.det = determinant(n.m);
    if (!(std::fabs(n.det) > 1e-12 * norm * norm * norm)) {
        throw Error(kSource, "the matrix " + matrix_text(given) + " is singular (determinant " + number_text(n.det) + ")");
    }
    return n;
}

// Whether an isotropic input stays isotropic under the tangent-plane map m: M2 = c R (a scaled
// rotation or reflection). `rotation`: c = 1.
bool keeps_isotropy(const Mat3& m, bool& rotation) {
    const double a = m(0, 0), b = m(0, 1), c = m(1, 0), d = m(1, 1);
    const double n1 = a * a + c * c, n2 = b * b + d * d, cross = a * b + c * d, s = std::max(n1, n2);
    const bool isotropic = std::fabs(n1 - n2) <= 1e-12 * s && std::fabs(cross) <= 1e-12 * s;
    rotation = isotropic && std::fabs(n1 - 1.0) <= 1e-12;
    return isotropic;
}

// D' at the cell centres (d_phi columns) from the projected-area density (see the header).
detail::Tables transformed_d(const NpfModel& in, const detail::Tables& d, const NormalMatrix& n, int d_phi) {
    const std::size_t C = in.channel_count();
    const Mat3 m_inv = inverse(n.m, n.det);
    const double inv_det = 1.0 / std::fabs(n.det);
    detail::Tables d2 = zero_tables(C, in.d_theta, d_phi);
    for_each_cell_centre(in.d_theta, d_phi, equation::theta_h_centre, [&](std::size_t cell, const Dir& h) {
        double len = 0.0;
        const Dir ho = mapped_unit(m_inv, h, len);
        if (!(ho.z > 0.0)) return;  // from below the horizon: no facets there
        const double jacobian = inv_det / (len * len * len) * ho.z / h.z;
        const Bilinear b = d_position(ho, in.d_theta, in.d_phi);
        for (std::size_t c = 0; c < C; ++c) d2.row(c)[cell] = at(d.row(c), b) * jacobian;
    });
    return d2;
}

// D' renormalised to projected area 1 per channel, the input's own area moved into base.rho_s so
// that the BRDF keeps its scale (it is 1 up to the SVD's truncation for a converted file). The
// raw area of each channel with a lobe over the input's.
std::vector<double> renormalise_d(const NpfModel& in, const std::vector<double>& area_in, int d_phi, const Mat3& given,
                                  detail::Tables& d2, NpfModel& base) {
    const std::vector<double> area_raw = detail::projected_areas(d2, in.d_theta, d_phi);
    std::vector<double> area_ratio;
    for (std::size_t c = 0; c < in.channel_count(); ++c) {
        if (!(area_in[c] > 0.0)) continue;  // no specular lobe in this channel: nothing to keep
        if (!(area_raw[c] > 0.0)) {
            throw Error(kSource, "the matrix " + matrix_text(given) + " leaves channel " + std::to_string(c) +
                                     " with no normals above the horizon");
        }
        double* row = d2.row(c);
        for (std::size_t k = 0; k < d2.cells; ++k) row[k] /= area_raw[c];
        base.rho_s[c] = float(base.rho_s[c] * area_in[c]);
        area_ratio.push_back(area_raw[c] / area_in[c]);
    }
    return area_ratio;
}

// G'(w) = G(M^T w / |M^T w|): the ray map of the transformed microsurface, at g_phi columns, with
// G's gauge (its value at normal incidence) kept as it was; the change goes into base.rho_s,
// which leaves the BRDF as it is. For tangent-plane maps the normal maps to itself and this is a
// rounding-level correction.
detail::Tables transformed_g(const NpfModel& in, const Mat3& m, int g_phi, NpfModel& base) {
    const std::size_t C = in.channel_count();
    const detail::Tables g = detail::expand(in.G, C);
    const Mat3 mt = transpose(m);
    detail::Tables g2 = zero_tables(C, in.g_theta, g_phi);
    for_each_cell_centre(in.g_theta, g_phi, equation::theta_centre, [&](std::size_t cell, const Dir& w) {
        double len = 0.0;
        const Dir wo = mapped_unit(mt, w, len);
        if (!(wo.z > 0.0)) return;
        const Bilinear b = g_position(wo, in.g_theta, in.g_phi);
        for (std::size_t c = 0; c < C; ++c) g2.row(c)[cell] = at(g.row(c), b);
    });
    const std::vector<double> g0_in = first_row_means(g, in.g_phi), g0_out = first_row_means(g2, g_phi);
    for (std::size_t c = 0; c < C; ++c) {
        if (!(g0_out[c] > 0.0) || !(g0_in[c] > 0.0)) continue;
        const double r = g0_in[c] / g0_out[c];
        double* row = g2.row(c);
        for (std::size_t k = 0; k < g2.cells; ++k) row[k] *= r;
        base.rho_s[c] = float(base.rho_s[c] / (r * r));
    }
    return g2;
}

void record_transform(const NpfModel& in, const NpfModel& out, const std::string& label, bool tangent,
                      const std::vector<double>& area_ratio, EditRecord& record) {
    record.summary = label + (tangent ? "" : " (tilting)") + ": D " + std::to_string(out.d_theta) + " x " +
                     std::to_string(out.d_phi) + ", G " + std::to_string(out.g_theta) + " x " + std::to_string(out.g_phi) +
                     "; projected area of D on the grid " + range_text(area_ratio) +
                     " of the input's before renormalisation to 1; SVD ranks D " + std::to_string(out.D.rank) +
                     " (keeps " + number_text(out.D.kept_ratio, 6) + " of the edited tables; the input kept " +
                     number_text(in.D.kept_ratio, 6) + "), G " + std::to_string(out.G.rank) + " (keeps " +
                     number_text(out.G.kept_ratio, 6) + "; input " + number_text(in.G.kept_ratio, 6) + ")";
    if (!tangent) {
        detail::warn(&record, "the matrix tilts the normal distribution (a mean-slope offset): D was cut at the horizon "
                              "and renormalised, and G's directional transform is only approximately consistent "
                              "with it (docs/editing.md)");
    }
}

}  // namespace

Mat3 stretch_matrix(double tangent, double bitangent) {
    check_factor(tangent, "the tangent stretch");
    check_factor(bitangent, "the bitangent stretch");
    Mat3 m;
    m(0, 0) = tangent;
    m(1, 1) = bitangent;
    return m;
}

Mat3 rotation_matrix(double degrees) {
    if (!std::isfinite(degrees)) throw Error(kSource, "the rotation angle is not a finite number");
    Mat3 m;
    if (degrees == 0.0) return m;
    const double a = degrees * kPiD / 180.0, c = std::cos(a), s = std::sin(a);
    m(0, 0) = c;
    m(0, 1) = -s;
    m(1, 0) = s;
    m(1, 1) = c;
    return m;
}

Mat3 roughness_matrix(double scale) {
    check_factor(scale, "the roughness scale");
    return stretch_matrix(scale, scale);
}

std::string matrix_text(const Mat3& m) {
    std::string s = "[";
    for (int i = 0; i < 3; ++i) {
        s += i ? ", [" : "[";
        for (int j = 0; j < 3; ++j) s += (j ? ", " : "") + number_text(m(i, j) == 0.0 ? 0.0 : m(i, j), 6);
        s += "]";
    }
    return s + "]";
}

std::vector<double> projected_area(const NpfModel& model) {
    return detail::projected_areas(detail::expand(model.D, model.channel_count()), model.d_theta, model.d_phi);
}

NpfModel transform_ndf(const NpfModel& in, const Mat3& given, const NdfTransformOptions& options, EditRecord* record) {
    const NormalMatrix n = normal_matrix(given, options);
    const Mat3& m = n.m;
    const std::string label = "ndf transform M = " + matrix_text(m);
    if (m == Mat3::identity()) {
        if (record) record->summary = label + ": the identity, nothing changed";
        return in;
    }
    const bool tangent = tangent_plane(m);
    bool isotropic_out = false, rotation = false;
    if (in.isotropic() && tangent) {
        isotropic_out = keeps_isotropy(m, rotation);
        if (rotation) {
            if (record) record->summary = label + ": a rotation of an isotropic material, nothing changed";
            return in;
        }
    }
    const int d_phi = in.d_phi > 1 || isotropic_out ? in.d_phi : (options.phi_cells > 0 ? options.phi_cells : 2 * in.d_theta);
    const int g_phi = in.g_phi > 1 || isotropic_out ? in.g_phi : (options.phi_cells > 0 ? options.phi_cells : 2 * in.g_theta);

    NpfModel base = in;
    const detail::Tables d = detail::expand(in.D, in.channel_count());
    detail::Tables d2 = transformed_d(in, d, n, d_phi);
    const std::vector<double> area_in = detail::projected_areas(d, in.d_theta, in.d_phi);
    const std::vector<double> area_ratio = renormalise_d(in, area_in, d_phi, given, d2, base);
    const detail::Tables g2 = transformed_g(in, m, g_phi, base);
    NpfModel out = detail::recompress(base, d2, d_phi, g2, g_phi, in, options.recompress);
    if (in.has_detail()) {
        // Kept where the transform leaves its coordinates alone; a reshaped lobe drops it.
        out.detail_grid = in.detail_grid;
        out.detail = in.detail;
        if (!rotation_about_normal(m)) {
            detail::drop_detail(out, record, "the transform reshapes the lobe the residual was fitted to");
        }
    }
    out.validate(kSource);
    if (record) record_transform(in, out, label, tangent, area_ratio, *record);
    return out;
}

}  // namespace npf::edit
