// RGL files read and checked (RglBrdf::from_tensor_file): the grids, the tables, the value bound
// and what `npf info` shows. Evaluation is rgl_brdf.cpp's.
#include <npf/materials/rgl_brdf.h>

#include <npf/core/error.h>
#include <npf/core/number_text.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace npf {

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

const TensorField& float_field(const TensorFile& file, const std::string& name, std::size_t rank) {
    const TensorField& f = file.require(name);
    file.expect_dtype(f, DType::F32);
    file.expect_rank(f, rank);
    return f;
}

struct AngleGrids {
    std::vector<float> phi_i, theta_i;
    bool isotropic = true;
    int reduction = 1;
};

AngleGrids read_angle_grids(const TensorFile& file) {
    const std::string& src = file.source();
    AngleGrids g;
    const TensorField& phi_field = float_field(file, "phi_i", 1);
    const TensorField& theta_field = float_field(file, "theta_i", 1);
    g.phi_i = file.to_float(phi_field);
    g.theta_i = file.to_float(theta_field);
    check_ascending(src, "phi_i", g.phi_i);
    check_ascending(src, "theta_i", g.theta_i);
    if (g.theta_i.front() < -1e-5f || g.theta_i.back() > 0.5f * kPi + 1e-5f) {
        throw Error(src, "field 'theta_i' leaves [0, pi/2]: " + join_floats(g.theta_i, 6));
    }
    // The reference readers call a file isotropic iff it has at most two phi_i entries.
    g.isotropic = g.phi_i.size() <= 2;
    if (g.isotropic) return g;
    const float span = g.phi_i.back() - g.phi_i.front();
    const float k = 2.f * kPi / span;
    const int reduction = int(std::lround(k));
    if ((reduction != 1 && reduction != 2 && reduction != 4) || std::fabs(k - float(reduction)) > 0.01f) {
        throw Error(src, "field 'phi_i' spans " + std::to_string(span) +
                             " rad: only the full circle, a half or a quarter (reductions 1, 2, 4) are supported");
    }
    g.reduction = reduction;
    // Folded queries have phi_i in [-pi, -pi + 2 pi / reduction]; a grid elsewhere would be
    // silently clamped, so it must cover exactly that interval.
    const float expected_end = -kPi + 2.f * kPi / float(reduction);
    if (std::fabs(g.phi_i.front() + kPi) > 1e-3f || std::fabs(g.phi_i.back() - expected_end) > 1e-3f) {
        throw Error(src, "field 'phi_i' runs from " + std::to_string(g.phi_i.front()) + " to " +
                             std::to_string(g.phi_i.back()) + " rad; reduction " + std::to_string(reduction) +
                             " needs it to cover [-pi, " + std::to_string(expected_end) + "]");
    }
    return g;
}

// The measurement, `rgb` or `spectra`, and the channels it stores.
const TensorField& read_measurement(const TensorFile& file, Channels& channels) {
    const std::string& src = file.source();
    const TensorField* rgb = file.find("rgb");
    const TensorField* spectra = file.find("spectra");
    // Both would leave the reader to pick one silently, and the two readers of the RGL group
    // pick differently.
    if (rgb && spectra) throw Error(src, "holds both 'rgb' and 'spectra': which one is the measurement is ambiguous");
    if (spectra) {
        const TensorField& data = float_field(file, "spectra", 5);
        const TensorField& wl = float_field(file, "wavelengths", 1);
        std::vector<float> wavelengths = file.to_float(wl);
        check_ascending(src, "wavelengths", wavelengths);
        if (wavelengths.front() <= 0.f) throw Error(src, "field 'wavelengths' must be positive (nm)");
        if (data.shape[2] != wavelengths.size()) {
            throw Error(src, "field 'spectra' has shape " + data.shape_string() + " but there are " +
                                 std::to_string(wavelengths.size()) + " wavelengths");
        }
        channels = Channels::spectral(std::move(wavelengths));
        return data;
    }
    if (!rgb) throw Error(src, "missing required field 'rgb' or 'spectra'");
    const TensorField& data = float_field(file, "rgb", 5);
    if (data.shape[2] != 3) {
        throw Error(src, "field 'rgb' has shape " + data.shape_string() + "; its third dimension must be 3");
    }
    channels = Channels::rgb();
    return data;
}

// A field's values: finite, and within kMaxMaterialValue (a finite but absurd value would turn
// into infinities downstream, in sums and squares).
std::vector<float> bounded_values(const TensorFile& file, const TensorField& f) {
    std::vector<float> v = file.to_float(f);
    for (std::size_t i = 0; i < v.size(); ++i) {
        if (!std::isfinite(v[i])) {
            throw Error(file.source(), "field '" + f.name + "' holds a non-finite value (" + std::to_string(v[i]) +
                                           ") at index " + std::to_string(i));
        }
        if (std::fabs(v[i]) > kMaxMaterialValue) {
            char text[32];
            std::snprintf(text, sizeof text, "%g", double(v[i]));
            throw Error(file.source(), "field '" + f.name + "' holds an out-of-range value (" + text + ") at index " +
                                           std::to_string(i));
        }
    }
    return v;
}

// A density and a projected area cannot be negative; the reference readers do not check, but a
// negative value here would flip the sign of f_r after the channel clamp.
std::vector<float> non_negative_values(const TensorFile& file, const TensorField& f) {
    std::vector<float> v = bounded_values(file, f);
    for (std::size_t i = 0; i < v.size(); ++i) {
        if (v[i] < 0.f) {
            throw Error(file.source(), "field '" + f.name + "' holds a negative value (" + std::to_string(v[i]) +
                                           ") at index " + std::to_string(i));
        }
    }
    return v;
}

// Stored [slice][channel][H][W]; kept [slice][H][W][channel], so that the corners of one
// direction pair hold every channel in a few contiguous cache lines (a spectral pair otherwise
// touches a separate line per channel and corner).
std::vector<float> channels_last(const std::vector<float>& stored, std::size_t slices, std::size_t channels,
                                 std::size_t plane) {
    std::vector<float> kept(stored.size());
    for (std::size_t slice = 0; slice < slices; ++slice) {
        const float* from = stored.data() + slice * channels * plane;
        float* to = kept.data() + slice * channels * plane;
        for (std::size_t c = 0; c < channels; ++c)
            for (std::size_t k = 0; k < plane; ++k) to[k * channels + c] = from[c * plane + k];
    }
    return kept;
}

struct JacobianFlag {
    bool on = true;
    std::string note;  // for `npf info`
};

JacobianFlag read_jacobian(const TensorFile& file) {
    const TensorField* jac = file.find("jacobian");
    if (!jac) return {true, "field absent; 1 assumed, as the reference readers do"};
    file.expect_dtype(*jac, DType::U8);
    if (jac->count != 1) throw Error(file.source(), "field 'jacobian' must hold exactly one u8");
    // A flag: any other value is a damaged file, not a third meaning.
    const std::uint8_t flag = file.payload(*jac)[0];
    if (flag > 1) throw Error(file.source(), "field 'jacobian' is " + std::to_string(flag) + "; it must be 0 or 1");
    return flag != 0 ? JacobianFlag{true, "1 (data are the ratio to the VNDF pdf)"} : JacobianFlag{false, "0 (data are f_r cos)"};
}

// Negative (out-of-gamut) values: renderers differ on them (the RGL loader and npf clamp them to
// 0, Mitsuba's `measured` keeps them), so a file that holds them says so.
std::string negative_values_note(const std::vector<float>& stored) {
    std::size_t negative = 0;
    double negative_sum = 0.0, positive_sum = 0.0, lowest = 0.0;
    for (float v : stored) {
        if (v < 0.f) ++negative, negative_sum -= double(v), lowest = std::min(lowest, double(v));
        else positive_sum += double(v);
    }
    if (negative == 0) return "none";
    char text[200];
    std::snprintf(text, sizeof text,
                  "%zu of %zu stored values (%.3g %%), lowest %.4g, together %.3g %% of the positive values' sum; "
                  "clamped to 0 when evaluated (npf eval --raw keeps them)",
                  negative, stored.size(), 100.0 * double(negative) / double(std::max<std::size_t>(stored.size(), 1)), lowest,
                  positive_sum > 0.0 ? 100.0 * negative_sum / positive_sum : 0.0);
    return text;
}

// The file's `description` and `version`, checked.
void read_header_fields(const TensorFile& file, BrdfInfo& info) {
    const std::string& src = file.source();
    if (const TensorField* d = file.find("description")) {
        if (d->dtype != DType::U8) throw Error(src, "field 'description' must be u8 text");
        info.description = file.to_string(*d);
    }
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
}

// The `valid` mask, one bit per data node, packed (another size is a mask of some other grid):
// how many are set.
std::string valid_mask_note(const TensorFile& file, const TensorField& valid, std::size_t nP, std::size_t nT,
                            std::uint64_t Hd, std::uint64_t Wd) {
    const std::uint64_t nodes = std::uint64_t(nP) * nT * Hd * Wd;
    file.expect_dtype(valid, DType::U8);
    file.expect_rank(valid, 1);
    if (valid.count != (nodes + 7) / 8)
        throw Error(file.source(), "field 'valid' holds " + std::to_string(valid.count) + " bytes; one bit per data node of " +
                                       std::to_string(nP) + " x " + std::to_string(nT) + " x " + std::to_string(Hd) +
                                       " x " + std::to_string(Wd) + " needs " + std::to_string((nodes + 7) / 8));
    std::uint64_t set = 0;
    const std::uint8_t* bits = file.payload(valid);
    for (std::uint64_t i = 0; i < nodes; ++i) set += (bits[i / 8] >> (7 - i % 8)) & 1u;
    return std::to_string(set) + " of " + std::to_string(nodes) + " bits set (not used by evaluation)";
}

std::string grid_text(const TensorField& f) {
    std::string s;
    for (std::size_t i = 0; i < f.shape.size(); ++i) s += (i ? " x " : "") + std::to_string(f.shape[i]);
    return s;
}

}  // namespace

std::unique_ptr<RglBrdf> RglBrdf::load(const std::string& path) {
    return from_tensor_file(TensorFile::read(path));
}

std::unique_ptr<RglBrdf> RglBrdf::from_tensor_file(const TensorFile& file) {
    const std::string& src = file.source();
    std::unique_ptr<RglBrdf> b(new RglBrdf());
    AngleGrids grids = read_angle_grids(file);
    b->m_phi_i = std::move(grids.phi_i);
    b->m_theta_i = std::move(grids.theta_i);
    b->m_isotropic = grids.isotropic;
    if (!grids.isotropic) b->m_reduction = grids.reduction;
    const std::size_t nP = b->m_phi_i.size(), nT = b->m_theta_i.size();

    const TensorField& ndf = float_field(file, "ndf", 2);
    const TensorField& sigma = float_field(file, "sigma", 2);
    const TensorField& vndf = float_field(file, "vndf", 4);
    const TensorField& lum = float_field(file, "luminance", 4);
    auto expect_leading = [&](const TensorField& f) {
        if (f.shape[0] != nP || f.shape[1] != nT) {
            throw Error(src, "field '" + f.name + "' has shape " + f.shape_string() +
                                 ", whose leading dimensions must be [phi_i, theta_i] = [" +
                                 std::to_string(nP) + ", " + std::to_string(nT) + "]");
        }
    };
    expect_leading(vndf);
    expect_leading(lum);
    const TensorField& data = read_measurement(file, b->m_info.channels);
    expect_leading(data);
    const std::uint64_t Hd = data.shape[3], Wd = data.shape[4];
    if (Hd != Wd) throw Error(src, "field '" + data.name + "' data grid " + data.shape_string() + " is not square");
    if (lum.shape[2] != Hd || lum.shape[3] != Wd) {
        throw Error(src, "field 'luminance' has shape " + lum.shape_string() +
                             ", whose inner dimensions must equal the data grid of '" + data.name + "' " +
                             data.shape_string());
    }

    std::vector<float> ndf_values = non_negative_values(file, ndf), sigma_values = non_negative_values(file, sigma);
    const float ndf_max = *std::max_element(ndf_values.begin(), ndf_values.end());
    const float sigma_min = *std::min_element(sigma_values.begin(), sigma_values.end());
    b->m_ndf = PiecewiseLinear2D(ndf.shape[1], ndf.shape[0], 1, std::move(ndf_values), false, src + ": field 'ndf'");
    b->m_sigma = PiecewiseLinear2D(sigma.shape[1], sigma.shape[0], 1, std::move(sigma_values), false,
                                   src + ": field 'sigma'");
    b->m_vndf = PiecewiseLinear2D(vndf.shape[3], vndf.shape[2], nP * nT, bounded_values(file, vndf), true,
                                  src + ": field 'vndf'");
    b->m_luminance = PiecewiseLinear2D(lum.shape[3], lum.shape[2], nP * nT, bounded_values(file, lum), true,
                                       src + ": field 'luminance'");
    // Data tables are used at face value; only their finiteness is checked (validity of the
    // grid sizes is checked by the same constructor, on one slice's worth of shape).
    const std::vector<float> stored = bounded_values(file, data);
    if (Hd < 2) throw Error(src, "field '" + data.name + "' data grid must be at least 2 x 2");
    const std::size_t channels = std::size_t(data.shape[2]);
    b->m_data = channels_last(stored, nP * nT, channels, std::size_t(Hd * Wd));
    b->m_channel_count = channels;
    b->m_data_height = std::size_t(Hd);
    b->m_data_width = std::size_t(Wd);
    const JacobianFlag jacobian = read_jacobian(file);
    b->m_jacobian = jacobian.on;

    // The value bound (brdf.h): every value is an interpolation of stored ones with weights in
    // [0, 1], so |data| <= its largest entry; with the Jacobian it is multiplied by ndf / (4 sigma),
    // where the interpolated sigma is at least its smallest node (a zero node lets it approach 0:
    // no bound). f_r cos(theta_o) bounds the projected form, as cos(theta_i) <= 1.
    double data_max = 0.0;
    for (float v : stored) data_max = std::max(data_max, double(std::fabs(v)));
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
    read_header_fields(file, info);
    if (!b->m_isotropic) {
        info.details.emplace_back("phi_i reduction", std::to_string(b->m_reduction) + " (phi_i covers 2 pi / " +
                                                         std::to_string(b->m_reduction) + ")");
    }
    info.details.emplace_back("phi_i", std::to_string(nP) + " values: " + join_floats(b->m_phi_i, 5));
    info.details.emplace_back("theta_i", std::to_string(nT) + " values: " + join_floats(b->m_theta_i, 5));
    info.details.emplace_back("data grid", grid_text(data) + " (" + data.name + ")");
    info.details.emplace_back("ndf grid", grid_text(ndf));
    info.details.emplace_back("sigma grid", grid_text(sigma));
    info.details.emplace_back("vndf grid", grid_text(vndf));
    info.details.emplace_back("jacobian", jacobian.note);
    info.details.emplace_back("negative values", negative_values_note(stored));
    if (const TensorField* valid = file.find("valid"))
        info.details.emplace_back("valid mask", valid_mask_note(file, *valid, nP, nT, Hd, Wd));
    return b;
}

}  // namespace npf
