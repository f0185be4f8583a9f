#include <npf/core/clamp.h>
#include <npf/materials/rgl_brdf.h>
#include "rgl_u_space.h"
#include <npf/core/brdf.h>
#include <npf/core/error.h>
#include <npf/core/number_text.h>
#include <npf/core/text.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace npf {

using rgl::phi_to_u;
using rgl::theta_to_u;
using rgl::u_to_phi;
using rgl::u_to_theta;

namespace {

std::string join_floats(const std::vector<float>& v, int precision) {
    std::ostringstream os;
    os.precision(precision);
    for (std::size_t i = 0; i < v.size(); ++i) os << (i ? " " : "") << v[i];
    return os.str();
}

void check_ascending(const std::string& source, const std::string& name, const std::vector<float>& v) {
    if (v.empty()) throw Error(source, "field '" + name + "' is empty");
    for (std::size_t i = 0; i < v.size(); ++i) {
        if (!std::isfinite(v[i])) throw Error(source, "field '" + name + "' holds a non-finite value");
        if (i > 0 && !(v[i] > v[i - 1])) {
            throw Error(source, "field '" + name + "' is not strictly ascending at index " + std::to_string(i));
        }
    }
}

// The sign flips that fold an anisotropic query into the stored azimuth range (Mitsuba 3's
// rule for files whose phi_i grid covers 1/2 or 1/4 of the circle).
struct Fold {
    bool flip_x = false, flip_y = false;
    Vec3 apply(Vec3 w) const {
        if (flip_x) w.x = -w.x;
        if (flip_y) w.y = -w.y;
        return w;
    }
};

Fold fold_for(int reduction, const Vec3& wi) {
    Fold f;
    if (reduction == 2) {
        f.flip_x = f.flip_y = !std::signbit(wi.y);
    } else if (reduction == 4) {
        f.flip_y = !std::signbit(wi.y);
        f.flip_x = !std::signbit(wi.x);
    }
    return f;
}

}  // namespace

struct RglBrdf::DirectionState {
    Vec3 wi, wh;          // folded
    float theta_i = 0.f, phi_i = 0.f;
    Vec2 u_h;             // half vector in u-space (relative azimuth if isotropic)
    Vec2 u_i;             // wi in u-space
    SliceBlend params;    // (phi_i, theta_i) blend of the conditional tables
    Vec2 xi;              // data-square position
    float vndf_density = 0.f;
};

std::unique_ptr<RglBrdf> RglBrdf::load(const std::string& path) {
    return from_tensor_file(TensorFile::read(path));
}

std::unique_ptr<RglBrdf> RglBrdf::from_tensor_file(const TensorFile& file) {
    const std::string& src = file.source();
    std::unique_ptr<RglBrdf> b(new RglBrdf());

    auto float_field = [&](const std::string& name, std::size_t rank) -> const TensorField& {
        const TensorField& f = file.require(name);
        file.expect_dtype(f, DType::F32);
        file.expect_rank(f, rank);
        return f;
    };

    const TensorField& phi_field = float_field("phi_i", 1);
    const TensorField& theta_field = float_field("theta_i", 1);
    b->m_phi_i = file.to_float(phi_field);
    b->m_theta_i = file.to_float(theta_field);
    check_ascending(src, "phi_i", b->m_phi_i);
    check_ascending(src, "theta_i", b->m_theta_i);
    if (b->m_theta_i.front() < -1e-5f || b->m_theta_i.back() > 0.5f * kPi + 1e-5f) {
        throw Error(src, "field 'theta_i' leaves [0, pi/2]: " + join_floats(b->m_theta_i, 6));
    }
    const std::size_t nP = b->m_phi_i.size(), nT = b->m_theta_i.size();

    // The reference readers call a file isotropic iff it has at most two phi_i entries.
    b->m_isotropic = nP <= 2;
    if (!b->m_isotropic) {
        const float span = b->m_phi_i.back() - b->m_phi_i.front();
        const float k = 2.f * kPi / span;
        const int reduction = int(std::lround(k));
        if ((reduction != 1 && reduction != 2 && reduction != 4) || std::fabs(k - float(reduction)) > 0.01f) {
            throw Error(src, "field 'phi_i' spans " + std::to_string(span) +
                                 " rad: only the full circle, a half or a quarter (reductions 1, 2, 4) are supported");
        }
        b->m_reduction = reduction;
        // Folded queries have phi_i in [-pi, -pi + 2 pi / reduction]; a grid elsewhere would be
        // silently clamped, so it must cover exactly that interval.
        const float expected_end = -kPi + 2.f * kPi / float(reduction);
        if (std::fabs(b->m_phi_i.front() + kPi) > 1e-3f || std::fabs(b->m_phi_i.back() - expected_end) > 1e-3f) {
            throw Error(src, "field 'phi_i' runs from " + std::to_string(b->m_phi_i.front()) + " to " +
                                 std::to_string(b->m_phi_i.back()) + " rad; reduction " + std::to_string(reduction) +
                                 " needs it to cover [-pi, " + std::to_string(expected_end) + "]");
        }
    }

    const TensorField& ndf = float_field("ndf", 2);
    const TensorField& sigma = float_field("sigma", 2);
    const TensorField& vndf = float_field("vndf", 4);
    const TensorField& lum = float_field("luminance", 4);
    auto expect_leading = [&](const TensorField& f) {
        if (f.shape[0] != nP || f.shape[1] != nT) {
            throw Error(src, "field '" + f.name + "' has shape " + f.shape_string() +
                                 ", whose leading dimensions must be [phi_i, theta_i] = [" +
                                 std::to_string(nP) + ", " + std::to_string(nT) + "]");
        }
    };
    expect_leading(vndf);
    expect_leading(lum);

    const TensorField* rgb = file.find("rgb");
    const TensorField* spectra = file.find("spectra");
    const TensorField* data = nullptr;
    // Both would leave the reader to pick one silently, and the two readers of the RGL group
    // pick differently.
    if (rgb && spectra) throw Error(src, "holds both 'rgb' and 'spectra': which one is the measurement is ambiguous");
    if (spectra) {
        data = &float_field("spectra", 5);
        const TensorField& wl = float_field("wavelengths", 1);
        std::vector<float> wavelengths = file.to_float(wl);
        check_ascending(src, "wavelengths", wavelengths);
        if (wavelengths.front() <= 0.f) throw Error(src, "field 'wavelengths' must be positive (nm)");
        if (data->shape[2] != wavelengths.size()) {
            throw Error(src, "field 'spectra' has shape " + data->shape_string() + " but there are " +
                                 std::to_string(wavelengths.size()) + " wavelengths");
        }
        b->m_info.channels = Channels::spectral(std::move(wavelengths));
    } else if (rgb) {
        data = &float_field("rgb", 5);
        if (data->shape[2] != 3) {
            throw Error(src, "field 'rgb' has shape " + data->shape_string() + "; its third dimension must be 3");
        }
        b->m_info.channels = Channels::rgb();
    } else {
        throw Error(src, "missing required field 'rgb' or 'spectra'");
    }
    expect_leading(*data);
    const std::uint64_t Hd = data->shape[3], Wd = data->shape[4];
    if (Hd != Wd) throw Error(src, "field '" + data->name + "' data grid " + data->shape_string() + " is not square");
    if (lum.shape[2] != Hd || lum.shape[3] != Wd) {
        throw Error(src, "field 'luminance' has shape " + lum.shape_string() +
                             ", whose inner dimensions must equal the data grid of '" + data->name + "' " +
                             data->shape_string());
    }

    // A density and a projected area cannot be negative; the reference readers do not check,
    // but a negative value here would flip the sign of f_r after the channel clamp.
    // Every table: finite, and within kMaxMaterialValue (a finite but absurd value would turn
    // into infinities downstream, in sums and squares).
    auto bounded = [&](const TensorField& f, std::vector<float> v) {
        for (std::size_t i = 0; i < v.size(); ++i) {
            if (!std::isfinite(v[i])) {
                throw Error(src, "field '" + f.name + "' holds a non-finite value (" + std::to_string(v[i]) +
                                     ") at index " + std::to_string(i));
            }
            if (std::fabs(v[i]) > kMaxMaterialValue) {
                char text[32];
                std::snprintf(text, sizeof text, "%g", double(v[i]));
                throw Error(src, "field '" + f.name + "' holds an out-of-range value (" + text + ") at index " +
                                     std::to_string(i));
            }
        }
        return v;
    };
    auto non_negative = [&](const TensorField& f) {
        std::vector<float> v = bounded(f, file.to_float(f));
        for (std::size_t i = 0; i < v.size(); ++i) {
            if (v[i] < 0.f) {
                throw Error(src, "field '" + f.name + "' holds a negative value (" + std::to_string(v[i]) +
                                     ") at index " + std::to_string(i));
            }
        }
        return v;
    };
    std::vector<float> ndf_values = non_negative(ndf), sigma_values = non_negative(sigma);
    const float ndf_max = *std::max_element(ndf_values.begin(), ndf_values.end());
    const float sigma_min = *std::min_element(sigma_values.begin(), sigma_values.end());
    b->m_ndf = PiecewiseLinear2D(ndf.shape[1], ndf.shape[0], 1, std::move(ndf_values), false, src + ": field 'ndf'");
    b->m_sigma = PiecewiseLinear2D(sigma.shape[1], sigma.shape[0], 1, std::move(sigma_values), false,
                                   src + ": field 'sigma'");
    b->m_vndf = PiecewiseLinear2D(vndf.shape[3], vndf.shape[2], nP * nT, bounded(vndf, file.to_float(vndf)), true,
                                  src + ": field 'vndf'");
    b->m_luminance = PiecewiseLinear2D(lum.shape[3], lum.shape[2], nP * nT, bounded(lum, file.to_float(lum)), true,
                                       src + ": field 'luminance'");
    // Data tables are used at face value; only their finiteness is checked (validity of the
    // grid sizes is checked by the same constructor, on one slice's worth of shape).
    // Stored [slice][channel][H][W]; kept [slice][H][W][channel], so that the corners of one
    // direction pair hold every channel in a few contiguous cache lines (a spectral pair
    // otherwise touches a separate line per channel and corner).
    const std::vector<float> stored = bounded(*data, file.to_float(*data));
    if (Hd < 2) throw Error(src, "field '" + data->name + "' data grid must be at least 2 x 2");
    const std::size_t channels = std::size_t(data->shape[2]), plane = std::size_t(Hd * Wd);
    b->m_data.resize(stored.size());
    for (std::size_t slice = 0; slice < nP * nT; ++slice) {
        const float* from = stored.data() + slice * channels * plane;
        float* to = b->m_data.data() + slice * channels * plane;
        for (std::size_t c = 0; c < channels; ++c)
            for (std::size_t k = 0; k < plane; ++k) to[k * channels + c] = from[c * plane + k];
    }
    b->m_channel_count = channels;
    b->m_data_height = std::size_t(Hd);
    b->m_data_width = std::size_t(Wd);

    b->m_jacobian = true;
    std::string jacobian_note = "1";
    if (const TensorField* jac = file.find("jacobian")) {
        file.expect_dtype(*jac, DType::U8);
        if (jac->count != 1) throw Error(src, "field 'jacobian' must hold exactly one u8");
        // A flag: any other value is a damaged file, not a third meaning.
        const std::uint8_t flag = file.payload(*jac)[0];
        if (flag > 1) throw Error(src, "field 'jacobian' is " + std::to_string(flag) + "; it must be 0 or 1");
        b->m_jacobian = flag != 0;
        jacobian_note = b->m_jacobian ? "1 (data are the ratio to the VNDF pdf)" : "0 (data are f_r cos)";
    } else {
        jacobian_note = "field absent; 1 assumed, as the reference readers do";
    }

    // The value bound (brdf.h): every value is an interpolation of stored ones with weights in
    // [0, 1], so |data| <= its largest entry; with the Jacobian it is multiplied by ndf / (4 sigma),
    // where the interpolated sigma is at least its smallest node (a zero node lets it approach 0:
    // no bound). f_r cos(theta_o) bounds the projected form, as cos(theta_i) <= 1.
    double data_max = 0.0;
    for (float v : stored) data_max = std::max(data_max, double(std::fabs(v)));
    // Negative (out-of-gamut) values: renderers differ on them (the RGL loader and npf clamp them
    // to 0, Mitsuba's `measured` keeps them), so a file that holds them says so.
    std::size_t negative = 0;
    double negative_sum = 0.0, positive_sum = 0.0, lowest = 0.0;
    for (float v : stored) {
        if (v < 0.f) ++negative, negative_sum -= double(v), lowest = std::min(lowest, double(v));
        else positive_sum += double(v);
    }
    const double bound = !b->m_jacobian ? data_max
                         : data_max == 0.0 || ndf_max == 0.f ? 0.0
                                                             : data_max * double(ndf_max) / (4.0 * double(sigma_min));
    check_value_bound(src, bound, b->m_jacobian ? "data x ndf / (4 sigma), sigma down to " + number_text(sigma_min) : "data");

    BrdfInfo& info = b->m_info;
    info.value_bound = bound;
    info.format = "rgl";
    info.path = src;
    info.file_bytes = file.size_bytes();
    info.isotropic = b->m_isotropic;
    if (const TensorField* d = file.find("description")) {
        if (d->dtype != DType::U8) throw Error(src, "field 'description' must be u8 text");
        info.description = file.to_string(*d);
    }
    auto grid = [](const TensorField& f) {
        std::string s;
        for (std::size_t i = 0; i < f.shape.size(); ++i) s += (i ? " x " : "") + std::to_string(f.shape[i]);
        return s;
    };
    if (const TensorField* v = file.find("version")) {
        // The layout this reader implements is version 1.0 (every database file says so); a
        // later one may mean the fields differently, so it is refused rather than misread.
        const std::vector<double> ver = file.to_double(*v);
        std::ostringstream s;
        for (std::size_t i = 0; i < ver.size() && i < 4; ++i) s << (i ? "." : "") << ver[i];
        if (ver.size() > 4) s << "...";
        if (ver.size() != 2 || ver[0] != 1.0 || ver[1] != 0.0)
            throw Error(src, "field 'version' is " + (ver.empty() ? std::string("empty") : s.str()) +
                                 "; this reader knows the measurement layout 1.0 only");
        info.details.emplace_back("measurement version", s.str());
    }
    if (!b->m_isotropic) {
        info.details.emplace_back("phi_i reduction", std::to_string(b->m_reduction) + " (phi_i covers 2 pi / " +
                                                         std::to_string(b->m_reduction) + ")");
    }
    info.details.emplace_back("phi_i", std::to_string(nP) + " values: " + join_floats(b->m_phi_i, 5));
    info.details.emplace_back("theta_i", std::to_string(nT) + " values: " + join_floats(b->m_theta_i, 5));
    info.details.emplace_back("data grid", grid(*data) + " (" + data->name + ")");
    info.details.emplace_back("ndf grid", grid(ndf));
    info.details.emplace_back("sigma grid", grid(sigma));
    info.details.emplace_back("vndf grid", grid(vndf));
    info.details.emplace_back("jacobian", jacobian_note);
    {
        char text[200];
        std::snprintf(text, sizeof text,
                      "%zu of %zu stored values (%.3g %%), lowest %.4g, together %.3g %% of the positive values' sum; "
                      "clamped to 0 when evaluated (npf eval --raw keeps them)",
                      negative, stored.size(), 100.0 * double(negative) / double(std::max<std::size_t>(stored.size(), 1)), lowest,
                      positive_sum > 0.0 ? 100.0 * negative_sum / positive_sum : 0.0);
        info.details.emplace_back("negative values", negative == 0 ? std::string("none") : std::string(text));
    }
    if (const TensorField* valid = file.find("valid")) {
        // One bit per data node, packed: another size is a mask of some other grid.
        const std::uint64_t nodes = std::uint64_t(nP) * nT * Hd * Wd;
        file.expect_dtype(*valid, DType::U8);
        file.expect_rank(*valid, 1);
        if (valid->count != (nodes + 7) / 8)
            throw Error(src, "field 'valid' holds " + std::to_string(valid->count) + " bytes; one bit per data node of " +
                                 std::to_string(nP) + " x " + std::to_string(nT) + " x " + std::to_string(Hd) + " x " +
                                 std::to_string(Wd) + " needs " + std::to_string((nodes + 7) / 8));
        std::uint64_t set = 0;
        const std::uint8_t* bits = file.payload(*valid);
        for (std::uint64_t i = 0; i < nodes; ++i) set += (bits[i / 8] >> (7 - i % 8)) & 1u;
        info.details.emplace_back("valid mask", std::to_string(set) + " of " + std::to_string(nodes) +
                                                      " bits set (not used by evaluation)");
    }
    return b;
}

bool RglBrdf::prepare(Vec3 wi, Vec3 wo, DirectionState& st) const {
    if (!(wi.z > 0.f) || !(wo.z > 0.f)) return false;
    const Fold fold = fold_for(m_reduction, wi);
    st.wi = wi = fold.apply(wi);
    wo = fold.apply(wo);
    st.wh = normalize(wi + wo);  // wi.z + wo.z > 0, so never the zero vector

    st.theta_i = elevation(wi);
    st.phi_i = azimuth(wi);
    const float theta_h = elevation(st.wh);
    float phi_h = azimuth(st.wh);
    if (m_isotropic) phi_h -= st.phi_i;
    float u_phi_h = phi_to_u(phi_h);
    u_phi_h -= std::floor(u_phi_h);
    st.u_h = {theta_to_u(theta_h), u_phi_h};
    st.u_i = {theta_to_u(st.theta_i), phi_to_u(st.phi_i)};
    st.params = blend_two_parameters(m_phi_i.size(), locate_on_grid(m_phi_i, st.phi_i), m_theta_i.size(),
                                     locate_on_grid(m_theta_i, st.theta_i));
    st.xi = m_vndf.invert(st.u_h, st.params, &st.vndf_density);
    return true;
}

void RglBrdf::eval_data(const DirectionState& st, const ChannelQuery& query, float* out) const {
    // The bilinear corner weights of xi times the parameter-slice weights: up to 16 terms that
    // every channel shares; each channel then only adds its own index.
    const std::size_t W = m_data_width, H = m_data_height, C = m_channel_count;
    const float gx = clamp_range(st.xi.x, 0.f, 1.f) * float(W - 1);
    const float gy = clamp_range(st.xi.y, 0.f, 1.f) * float(H - 1);
    const std::size_t c = std::min(std::size_t(gx), W - 2), r = std::min(std::size_t(gy), H - 2);
    const float s = gx - float(c), t = gy - float(r);
    const float corner_w[4] = {(1 - s) * (1 - t), s * (1 - t), (1 - s) * t, s * t};
    const std::size_t corner_k[4] = {r * W + c, r * W + c + 1, (r + 1) * W + c, (r + 1) * W + c + 1};
    const float* base[16];
    float weight[16];
    int terms = 0;
    for (int j = 0; j < st.params.count; ++j) {
        const float* slice = m_data.data() + std::size_t(st.params.slice[j]) * H * W * C;
        for (int q = 0; q < 4; ++q) {
            base[terms] = slice + corner_k[q] * C;
            weight[terms] = st.params.weight[j] * corner_w[q];
            ++terms;
        }
    }

    auto finish = [&](float v) { return query.clamp_negative ? clamp_low(v, 0.f) : v; };
    const std::size_t n = query.size();
    constexpr std::size_t kMaxAccumulated = 512;
    if (n > 8 && C <= kMaxAccumulated) {
        // Many channels: accumulate the stored channels they read, a contiguous range, in one
        // vectorisable pass, then read the requested ones from the sums. (The range, not every
        // stored channel: the fitter asks a 195-wavelength file for a third of them per pass.)
        std::uint32_t lo = query.index0[0], hi = query.index1[0];
        for (std::size_t k = 1; k < n; ++k) lo = std::min(lo, query.index0[k]), hi = std::max(hi, query.index1[k]);
        float sum[kMaxAccumulated];
        for (std::size_t ch = lo; ch <= hi; ++ch) sum[ch] = weight[0] * base[0][ch];
        for (int k = 1; k < terms; ++k) {
            const float w = weight[k];
            const float* b = base[k];
            for (std::size_t ch = lo; ch <= hi; ++ch) sum[ch] += w * b[ch];
        }
        for (std::size_t k = 0; k < n; ++k) {
            const float v0 = sum[query.index0[k]];
            out[k] = finish(v0 + query.weight1[k] * (sum[query.index1[k]] - v0));
        }
        return;
    }
    // Few channels (RGB, hero wavelengths): gather just those, eight at a time and term by
    // term, so that each corner's cache line is visited once for all of them.
    for (std::size_t first = 0; first < n; first += 8) {
        const std::size_t count = std::min<std::size_t>(8, n - first);
        const std::uint32_t* i0 = query.index0.data() + first;
        const std::uint32_t* i1 = query.index1.data() + first;
        float lower[8] = {}, upper[8] = {};
        for (int term = 0; term < terms; ++term) {
            const float w = weight[term];
            const float* b = base[term];
            for (std::size_t k = 0; k < count; ++k) {
                lower[k] += w * b[i0[k]];
                upper[k] += w * b[i1[k]];
            }
        }
        for (std::size_t k = 0; k < count; ++k) {
            out[first + k] = finish(lower[k] + query.weight1[first + k] * (upper[k] - lower[k]));
        }
    }
}

void RglBrdf::eval_cos(const Vec3& wi, const Vec3& wo, const ChannelQuery& query, float* out) const {
    DirectionState st;
    if (!prepare(wi, wo, st)) {
        std::fill(out, out + query.size(), 0.f);
        return;
    }
    eval_data(st, query, out);
    if (m_jacobian) {
        const float sigma = m_sigma.eval(st.u_i, SliceBlend());
        const float factor = sigma > 0.f ? m_ndf.eval(st.u_h, SliceBlend()) / (4.f * sigma) : 0.f;
        for (std::size_t k = 0; k < query.size(); ++k) out[k] *= factor;
    }
}

float RglBrdf::pdf(const Vec3& wi, const Vec3& wo) const {
    DirectionState st;
    if (!prepare(wi, wo, st)) return 0.f;
    const float lum_density = m_luminance.eval(st.xi, st.params);
    const float sin_theta_h = std::sqrt(st.wh.x * st.wh.x + st.wh.y * st.wh.y);
    // u-space to solid angle (2 pi^2 u sin theta) and half vector to wo (4 wi.wh); the 1e-6
    // floor at the pole is the reference readers' own.
    const float jacobian = clamp_low(2.f * kPi * kPi * st.u_h.x * sin_theta_h, 1e-6f) * 4.f * dot(st.wi, st.wh);
    return jacobian > 0.f ? st.vndf_density * lum_density / jacobian : 0.f;
}

bool RglBrdf::sample(const Vec3& wi_in, const Vec2& u, const ChannelQuery& query, BrdfSample& s,
                     float* weight) const {
    if (weight) std::fill(weight, weight + query.size(), 0.f);
    s = BrdfSample();
    if (!(wi_in.z > 0.f)) return false;
    const Fold fold = fold_for(m_reduction, wi_in);
    DirectionState st;
    st.wi = fold.apply(wi_in);
    st.theta_i = elevation(st.wi);
    st.phi_i = azimuth(st.wi);
    st.u_i = {theta_to_u(st.theta_i), phi_to_u(st.phi_i)};
    st.params = blend_two_parameters(m_phi_i.size(), locate_on_grid(m_phi_i, st.phi_i), m_theta_i.size(),
                                     locate_on_grid(m_theta_i, st.theta_i));

    // Uniform -> luminance warp -> data square -> VNDF warp -> half vector (readers swap u).
    float lum_density = 0.f, vndf_density = 0.f;
    st.xi = m_luminance.sample({u.y, u.x}, st.params, &lum_density);
    st.u_h = m_vndf.sample(st.xi, st.params, &vndf_density);
    const float theta_h = u_to_theta(st.u_h.x);
    float phi_h = u_to_phi(st.u_h.y);
    if (m_isotropic) phi_h += st.phi_i;
    st.wh = spherical_direction(theta_h, phi_h);
    const float cos_d = dot(st.wi, st.wh);
    const Vec3 wo = st.wh * (2.f * cos_d) - st.wi;
    if (!(wo.z > 0.f) || !(cos_d > 0.f)) return false;

    const float jacobian = clamp_low(2.f * kPi * kPi * st.u_h.x * std::sin(theta_h), 1e-6f) * 4.f * cos_d;
    const float pdf = vndf_density * lum_density / jacobian;
    if (!(pdf > 0.f) || !std::isfinite(pdf)) return false;
    s.wo = fold.apply(wo);  // the flips are their own inverse
    s.pdf = pdf;
    if (weight) {
        eval_data(st, query, weight);
        float factor = 1.f / pdf;
        if (m_jacobian) {
            const float sigma = m_sigma.eval(st.u_i, SliceBlend());
            factor = sigma > 0.f ? m_ndf.eval(st.u_h, SliceBlend()) / (4.f * sigma * pdf) : 0.f;
        }
        for (std::size_t k = 0; k < query.size(); ++k) weight[k] *= factor;
    }
    return true;
}

}  // namespace npf
