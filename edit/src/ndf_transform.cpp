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
    Mat3 m = given;
    for (double& v : m.m) v /= given(2, 2);
    double norm = 0.0;
    for (double v : m.m) norm = std::max(norm, std::fabs(v));
    const double det = determinant(m);
    if (!(std::fabs(det) > 1e-12 * norm * norm * norm)) {
        throw Error(kSource, "the matrix " + matrix_text(given) + " is singular (determinant " + number_text(det) + ")");
    }
    const std::string label = "ndf transform M = " + matrix_text(m);
    if (m == Mat3::identity()) {
        if (record) record->summary = label + ": the identity, nothing changed";
        return in;
    }
    const bool tangent = tangent_plane(m);
    bool isotropic_out = false;
    if (in.isotropic() && tangent) {
        // An isotropic D stays isotropic under M2 = c R (a scaled rotation or reflection).
        const double a = m(0, 0), b = m(0, 1), c = m(1, 0), d = m(1, 1);
        const double n1 = a * a + c * c, n2 = b * b + d * d, cross = a * b + c * d, s = std::max(n1, n2);
        isotropic_out = std::fabs(n1 - n2) <= 1e-12 * s && std::fabs(cross) <= 1e-12 * s;
        if (isotropic_out && std::fabs(n1 - 1.0) <= 1e-12) {
            if (record) record->summary = label + ": a rotation of an isotropic material, nothing changed";
            return in;
        }
    }

    const std::size_t C = in.channel_count();
    const int d_phi = in.d_phi > 1 || isotropic_out ? in.d_phi : (options.phi_cells > 0 ? options.phi_cells : 2 * in.d_theta);
    const int g_phi = in.g_phi > 1 || isotropic_out ? in.g_phi : (options.phi_cells > 0 ? options.phi_cells : 2 * in.g_theta);

    const detail::Tables d = detail::expand(in.D, C), g = detail::expand(in.G, C);
    const std::vector<double> area_in = detail::projected_areas(d, in.d_theta, in.d_phi);
    const std::vector<double> g0_in = first_row_means(g, in.g_phi);

    // D' at the cell centres from the projected-area density (see the header).
    const Mat3 m_inv = inverse(m, det);
    const double inv_det = 1.0 / std::fabs(det);
    detail::Tables d2;
    d2.channels = C;
    d2.cells = std::size_t(in.d_theta) * std::size_t(d_phi);
    d2.v.assign(C * d2.cells, 0.0);
    for (int i = 0; i < in.d_theta; ++i) {
        const double theta = equation::theta_h_centre(i, in.d_theta);
        for (int j = 0; j < d_phi; ++j) {
            const double phi = d_phi == 1 ? 0.0 : equation::phi_centre(j, d_phi);
            const Dir h{std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
            const Dir q = times(m_inv, h);
            const double len = std::sqrt(q.x * q.x + q.y * q.y + q.z * q.z);
            const Dir ho{q.x / len, q.y / len, q.z / len};
            if (!(ho.z > 0.0)) continue;  // from below the horizon: no facets there
            const double jacobian = inv_det / (len * len * len) * ho.z / h.z;
            const Bilinear b = d_position(ho, in.d_theta, in.d_phi);
            const std::size_t cell = std::size_t(i) * std::size_t(d_phi) + std::size_t(j);
            for (std::size_t c = 0; c < C; ++c) d2.row(c)[cell] = at(d.row(c), b) * jacobian;
        }
    }
    const std::vector<double> area_raw = detail::projected_areas(d2, in.d_theta, d_phi);
    NpfModel base = in;
    std::vector<double> area_ratio;
    for (std::size_t c = 0; c < C; ++c) {
        if (!(area_in[c] > 0.0)) continue;  // no specular lobe in this channel: nothing to keep
        if (!(area_raw[c] > 0.0)) {
            throw Error(kSource, "the matrix " + matrix_text(given) + " leaves channel " + std::to_string(c) +
                                     " with no normals above the horizon");
        }
        double* row = d2.row(c);
        for (std::size_t k = 0; k < d2.cells; ++k) row[k] /= area_raw[c];
        // Projected area 1 (the gauge), with the input's own area moved into rho_s so that the
        // BRDF keeps its scale (it is 1 up to the SVD's truncation for a converted file).
        base.rho_s[c] = float(base.rho_s[c] * area_in[c]);
        area_ratio.push_back(area_raw[c] / area_in[c]);
    }

    // G'(w) = G(M^T w / |M^T w|): the ray map of the transformed microsurface.
    const Mat3 mt = transpose(m);
    detail::Tables g2;
    g2.channels = C;
    g2.cells = std::size_t(in.g_theta) * std::size_t(g_phi);
    g2.v.assign(C * g2.cells, 0.0);
    for (int i = 0; i < in.g_theta; ++i) {
        const double theta = equation::theta_centre(i, in.g_theta);
        for (int j = 0; j < g_phi; ++j) {
            const double phi = g_phi == 1 ? 0.0 : equation::phi_centre(j, g_phi);
            const Dir w{std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
            const Dir q = times(mt, w);
            const double len = std::sqrt(q.x * q.x + q.y * q.y + q.z * q.z);
            const Dir wo{q.x / len, q.y / len, q.z / len};
            if (!(wo.z > 0.0)) continue;
            const Bilinear b = g_position(wo, in.g_theta, in.g_phi);
            const std::size_t cell = std::size_t(i) * std::size_t(g_phi) + std::size_t(j);
            for (std::size_t c = 0; c < C; ++c) g2.row(c)[cell] = at(g.row(c), b);
        }
    }
    // Keep G's gauge (its value at normal incidence) as it was; the change goes into rho_s, which
    // leaves the BRDF as it is. For tangent-plane maps the normal maps to itself and this is a
    // rounding-level correction.
    const std::vector<double> g0_out = first_row_means(g2, g_phi);
    for (std::size_t c = 0; c < C; ++c) {
        if (!(g0_out[c] > 0.0) || !(g0_in[c] > 0.0)) continue;
        const double r = g0_in[c] / g0_out[c];
        double* row = g2.row(c);
        for (std::size_t k = 0; k < g2.cells; ++k) row[k] *= r;
        base.rho_s[c] = float(base.rho_s[c] / (r * r));
    }

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
    if (record) {
        record->summary = label + (tangent ? "" : " (tilting)") + ": D " + std::to_string(out.d_theta) + " x " +
                          std::to_string(out.d_phi) + ", G " + std::to_string(out.g_theta) + " x " +
                          std::to_string(out.g_phi) + "; projected area of D on the grid " + range_text(area_ratio) +
                          " of the input's before renormalisation to 1; SVD ranks D " + std::to_string(out.D.rank) +
                          " (keeps " + number_text(out.D.kept_ratio, 6) + " of the edited tables; the input kept " +
                          number_text(in.D.kept_ratio, 6) + "), G " + std::to_string(out.G.rank) + " (keeps " +
                          number_text(out.G.kept_ratio, 6) + "; input " + number_text(in.G.kept_ratio, 6) + ")";
        if (!tangent) {
            detail::warn(record, "the matrix tilts the normal distribution (a mean-slope offset): D was cut at the horizon "
                                 "and renormalised, and G's directional transform is only approximately consistent "
                                 "with it (docs/editing.md)");
        }
    }
    return out;
}

}  // namespace npf::edit
