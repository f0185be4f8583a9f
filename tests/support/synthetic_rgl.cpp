#include "synthetic_rgl.h"

#include <npf/core/error.h>
#include <npf/core/rec709_luminance.h>
#include <npf/core/vec.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <initializer_list>
#include <mutex>
#include <stdexcept>
#include <sys/stat.h>

namespace npf::testing {

namespace {

constexpr double kPi = npf::kPiD;

// Node coordinate c / (n - 1) on [0, 1]; a grid of one node sits at 0.
double node(int c, int n) { return n > 1 ? double(c) / double(n - 1) : 0.0; }

struct Dir {
    double x, y, z;
};

Dir direction(double theta, double phi) {
    const double s = std::sin(theta);
    return {s * std::cos(phi), s * std::sin(phi), std::cos(theta)};
}

// Anisotropic GGX (Trowbridge-Reitz) normal distribution, normalised so that
// integral D(m) cos(theta_m) dm = 1. Written as (cos^2 + sin^2 a)^2 so that it stays finite
// at theta = pi/2.
double ggx_d(double theta, double phi, double ax, double ay) {
    const double c = std::cos(theta), s = std::sin(theta);
    const double cp = std::cos(phi), sp = std::sin(phi);
    const double a = cp * cp / (ax * ax) + sp * sp / (ay * ay);
    const double q = c * c + s * s * a;
    return 1.0 / (kPi * ax * ay * q * q);
}

// Projected area of the GGX microsurface seen from (theta, phi): cos(theta) (1 + Lambda),
// exact for the Smith model: 1 at the normal, alpha(phi) / 2 at grazing angles.
double ggx_sigma(double theta, double phi, double ax, double ay) {
    const double c = std::cos(theta), s = std::sin(theta);
    const double cp = std::cos(phi), sp = std::sin(phi);
    const double alpha2 = cp * cp * ax * ax + sp * sp * ay * ay;
    return 0.5 * (c + std::sqrt(c * c + alpha2 * s * s));
}

void check_spec(const SyntheticRglSpec& spec) {
    if (spec.phi_count < 1 || spec.theta_count < 1 || spec.ndf_size < 1 || spec.vndf_size < 1 ||
        spec.data_size < 1 || spec.reduction < 1) {
        throw std::invalid_argument("SyntheticRglSpec: counts, sizes and reduction must be >= 1");
    }
    if (!(spec.alpha_x > 0.f) || !(spec.alpha_y > 0.f)) {
        throw std::invalid_argument("SyntheticRglSpec: alpha_x and alpha_y must be positive");
    }
    if (spec.spectral && spec.wavelengths.empty()) {
        throw std::invalid_argument("SyntheticRglSpec: a spectral file needs wavelengths");
    }
}

std::vector<std::uint64_t> u64_shape(std::initializer_list<int> dims) {
    std::vector<std::uint64_t> s;
    for (int d : dims) s.push_back(std::uint64_t(d));
    return s;
}

SyntheticField f32_field(const std::string& name, std::vector<std::uint64_t> shape,
                         const std::vector<float>& values) {
    SyntheticField f;
    f.name = name;
    f.shape = std::move(shape);
    f.set_floats(values);
    return f;
}

SyntheticField u8_field(const std::string& name, std::vector<std::uint64_t> shape,
                        std::vector<std::uint8_t> values) {
    SyntheticField f;
    f.name = name;
    f.dtype = DType::U8;
    f.shape = std::move(shape);
    f.bytes = std::move(values);
    return f;
}

}  // namespace

std::vector<float> SyntheticField::floats() const {
    if (dtype != DType::F32) throw std::logic_error("SyntheticField::floats: field '" + name + "' is not f32");
    std::vector<float> v(bytes.size() / 4);
    if (!v.empty()) std::memcpy(v.data(), bytes.data(), v.size() * 4);
    return v;
}

void SyntheticField::set_floats(const std::vector<float>& v) {
    dtype = DType::F32;
    bytes.resize(v.size() * 4);
    if (!v.empty()) std::memcpy(bytes.data(), v.data(), bytes.size());
}

namespace {

// The tables of a synthetic file, before they become fields.
struct SyntheticTables {
    bool isotropic = false;
    int nP = 0, nT = 0, V = 0, S = 0, ndf_rows = 0, ndf_cols = 0;
    double dax = 0.0, day = 0.0;  // the NDF's widths (their mean for an isotropic file)
    std::vector<float> phi_i, theta_i, ndf, sigma, vndf, data, lum;
};

// Incident grids. Anisotropic: -pi .. -pi + 2 pi / reduction inclusive, the interval that
// folded queries land in (docs/rgl-format.md sec. 7).
void fill_incident_grids(const SyntheticRglSpec& spec, SyntheticTables& t) {
    const int nP = t.nP, nT = t.nT;
    std::vector<float>& phi_i = t.phi_i;
    std::vector<float>& theta_i = t.theta_i;
    if (nP == 1) {
        phi_i = {0.f};
    } else if (nP == 2) {
        phi_i = {float(-kPi), float(kPi)};
    } else {
        const double span = 2.0 * kPi / double(spec.reduction);
        for (int k = 0; k < nP; ++k) phi_i.push_back(float(-kPi + span * node(k, nP)));
    }
    for (int l = 0; l < nT; ++l) theta_i.push_back(float(0.5 * kPi * node(l, nT)));
}

void fill_ndf(SyntheticTables& t) {
    const int ndf_rows = t.ndf_rows, ndf_cols = t.ndf_cols;
    const double dax = t.dax, day = t.day;
    // ndf and sigma in u-space: rows u_phi, columns u_theta.
    std::vector<float>& ndf = t.ndf;
    std::vector<float>& sigma = t.sigma;
    ndf.assign(std::size_t(ndf_rows) * ndf_cols, 0.f);
    sigma.assign(ndf.size(), 0.f);
    for (int r = 0; r < ndf_rows; ++r) {
        const double phi = (2.0 * node(r, ndf_rows) - 1.0) * kPi;
        for (int c = 0; c < ndf_cols; ++c) {
            const double u = node(c, ndf_cols), theta = 0.5 * kPi * u * u;
            ndf[std::size_t(r) * ndf_cols + c] = float(ggx_d(theta, phi, dax, day));
            sigma[std::size_t(r) * ndf_cols + c] = float(ggx_sigma(theta, phi, dax, day));
        }
    }
}

void fill_vndf(SyntheticTables& t) {
    const int nP = t.nP, nT = t.nT, V = t.V;
    const bool isotropic = t.isotropic;
    const double dax = t.dax, day = t.day;
    const std::vector<float>& phi_i = t.phi_i;
    const std::vector<float>& theta_i = t.theta_i;
    // vndf per incident slice (W4 of the format notes): max(0, wi.m) D(m) / sigma(wi) times the
    // u-space Jacobian 2 pi^2 u sin(theta_m), plus a tiny floor so no slice is all zero.
    const std::size_t vplane = std::size_t(V) * V;
    std::vector<float>& vndf = t.vndf;
    vndf.assign(std::size_t(nP) * nT * vplane, 0.f);
    for (int k = 0; k < nP; ++k) {
        for (int l = 0; l < nT; ++l) {
            const Dir wi = direction(theta_i[std::size_t(l)], phi_i[std::size_t(k)]);
            const double s_i = ggx_sigma(theta_i[std::size_t(l)], phi_i[std::size_t(k)], dax, day);
            float* slice = vndf.data() + (std::size_t(k) * nT + l) * vplane;
            double peak = 0.0;
            for (int r = 0; r < V; ++r) {
                double phi_m = (2.0 * node(r, V) - 1.0) * kPi;
                if (isotropic) phi_m += phi_i[std::size_t(k)];
                for (int c = 0; c < V; ++c) {
                    const double u = node(c, V), theta_m = 0.5 * kPi * u * u;
                    const Dir m = direction(theta_m, phi_m);
                    const double cosine = std::max(0.0, wi.x * m.x + wi.y * m.y + wi.z * m.z);
                    const double v = cosine * ggx_d(theta_m, phi_m, dax, day) / s_i * 2.0 * kPi * kPi * u *
                                     std::sin(theta_m);
                    slice[std::size_t(r) * V + c] = float(v);
                    peak = std::max(peak, v);
                }
            }
            const float floor = float(1e-5 * peak + 1e-9);
            for (std::size_t i = 0; i < vplane; ++i) slice[i] += floor;
        }
    }
}

// One incident slice's data planes, channel by channel.
void fill_data_slice(const SyntheticRglSpec& spec, int S, std::size_t nC, std::size_t base, double slice_factor,
                     std::vector<float>& data) {
    const std::size_t dplane = std::size_t(S) * S;
    const double rgb_scale[3] = {0.8, 0.5, 0.3};
    for (std::size_t ch = 0; ch < nC; ++ch) {
        double scale, wiggle;
        if (spec.spectral) {
            const double lambda = spec.wavelengths[ch];
            scale = 0.25 + 0.6 * std::clamp((lambda - 350.0) / 400.0, 0.0, 1.0);
            wiggle = 0.15 * std::sin(lambda / 47.0);
        } else {
            scale = rgb_scale[ch];
            wiggle = 0.1 * double(ch);
        }
        float* plane = data.data() + (base * nC + ch) * dplane;
        for (int r = 0; r < S; ++r) {
            const double y = node(r, S);
            for (int c = 0; c < S; ++c) {
                const double x = node(c, S);
                double v = 0.1 + 0.55 * (1.0 - 0.5 * x) + 0.2 * std::cos(2.0 * kPi * y + wiggle) * (1.0 - x) +
                           wiggle * x * y;
                v *= scale * slice_factor;
                if (!spec.spectral && ch == 2) {
                    const double d = std::hypot(x - 0.3, y - 0.5);
                    v -= 1.6 * scale * std::max(0.0, 1.0 - d / 0.3);
                }
                plane[std::size_t(r) * S + c] = float(v);
            }
        }
    }
}

// One incident slice's luminance plane from its data.
void fill_luminance_slice(const SyntheticRglSpec& spec, std::size_t nC, std::size_t dplane, std::size_t base,
                          const std::vector<float>& data, std::vector<float>& lum) {
    // Luminance of the data, floored so that it stays a positive density.
    float* lplane = lum.data() + base * dplane;
    const float* d0 = data.data() + base * nC * dplane;
    float peak = 0.f;
    for (std::size_t i = 0; i < dplane; ++i) {
        double y;
        if (spec.spectral) {
            y = 0.0;
            for (std::size_t ch = 0; ch < nC; ++ch) y += d0[ch * dplane + i];
            y /= double(nC);
        } else {
            y = npf::rec709_luminance(d0[i], d0[dplane + i], d0[2 * dplane + i]);
        }
        lplane[i] = float(y);
        peak = std::max(peak, lplane[i]);
    }
    const float floor = std::max(1e-3f * peak, 1e-6f);
    for (std::size_t i = 0; i < dplane; ++i) lplane[i] = std::max(lplane[i], floor);
}

// Data: a smooth positive pattern varying with channel, node and incident slice, with a
// diffuse floor; RGB blue dips below zero around xi = (0.3, 0.5) (out-of-gamut values).
void fill_data(const SyntheticRglSpec& spec, SyntheticTables& t) {
    const int nP = t.nP, nT = t.nT, S = t.S;
    const std::size_t nC = spec.spectral ? spec.wavelengths.size() : 3;
    const std::size_t dplane = std::size_t(S) * S;
    t.data.assign(std::size_t(nP) * nT * nC * dplane, 0.f);
    t.lum.assign(std::size_t(nP) * nT * dplane, 0.f);
    for (int k = 0; k < nP; ++k) {
        for (int l = 0; l < nT; ++l) {
            double slice_factor = 1.0 - 0.3 * node(l, nT);
            if (!t.isotropic) slice_factor += 0.1 * std::cos(double(t.phi_i[std::size_t(k)]));
            const std::size_t base = (std::size_t(k) * nT + l);
            fill_data_slice(spec, S, nC, base, slice_factor, t.data);
            fill_luminance_slice(spec, nC, dplane, base, t.data, t.lum);
        }
    }
}

}  // namespace

std::vector<SyntheticField> synthetic_rgl_fields(const SyntheticRglSpec& spec) {
    check_spec(spec);
    SyntheticTables t;
    t.isotropic = spec.phi_count <= 2;
    t.nP = spec.phi_count, t.nT = spec.theta_count;
    t.V = spec.vndf_size, t.S = spec.data_size;
    t.ndf_rows = t.isotropic ? 2 : spec.ndf_size, t.ndf_cols = spec.ndf_size;
    const double ax = spec.alpha_x, ay = spec.alpha_y;
    // An isotropic file needs an azimuth-independent NDF.
    const double iso_alpha = 0.5 * (ax + ay);
    t.dax = t.isotropic ? iso_alpha : ax, t.day = t.isotropic ? iso_alpha : ay;
    fill_incident_grids(spec, t);
    fill_ndf(t);
    fill_vndf(t);
    fill_data(spec, t);

    const int nP = t.nP, nT = t.nT, V = t.V, S = t.S, ndf_rows = t.ndf_rows, ndf_cols = t.ndf_cols;
    const std::size_t nC = spec.spectral ? spec.wavelengths.size() : 3;
    std::vector<SyntheticField> fields;
    fields.push_back(u8_field("description", {std::uint64_t(spec.description.size())},
                              std::vector<std::uint8_t>(spec.description.begin(), spec.description.end())));
    fields.push_back(u8_field("jacobian", {1}, {std::uint8_t(spec.jacobian ? 1 : 0)}));
    fields.push_back(f32_field("phi_i", u64_shape({nP}), t.phi_i));
    fields.push_back(f32_field("theta_i", u64_shape({nT}), t.theta_i));
    fields.push_back(f32_field("ndf", u64_shape({ndf_rows, ndf_cols}), t.ndf));
    fields.push_back(f32_field("sigma", u64_shape({ndf_rows, ndf_cols}), t.sigma));
    fields.push_back(f32_field("vndf", u64_shape({nP, nT, V, V}), t.vndf));
    fields.push_back(f32_field("luminance", u64_shape({nP, nT, S, S}), t.lum));
    if (spec.spectral) {
        fields.push_back(f32_field("wavelengths", {std::uint64_t(nC)}, spec.wavelengths));
        fields.push_back(f32_field("spectra", u64_shape({nP, nT, int(nC), S, S}), t.data));
    } else {
        fields.push_back(f32_field("rgb", u64_shape({nP, nT, 3, S, S}), t.data));
    }
    return fields;
}

TensorFileWriter to_writer(const std::vector<SyntheticField>& fields) {
    TensorFileWriter w;
    for (const SyntheticField& f : fields) {
        std::uint64_t count = 1;
        for (std::uint64_t e : f.shape) {
            if (__builtin_mul_overflow(count, e, &count)) {
                throw std::invalid_argument("to_writer: field '" + f.name + "' shape overflows");
            }
        }
        const std::uint64_t step = dtype_size(f.dtype);
        if (step == 0 || count > f.bytes.size() / step || count * step != f.bytes.size()) {
            throw std::invalid_argument("to_writer: field '" + f.name +
                                        "' payload size does not match its shape and dtype");
        }
        w.add(f.name, f.dtype, f.shape, f.bytes.data());
    }
    return w;
}

SyntheticField* find_field(std::vector<SyntheticField>& fields, const std::string& name) {
    for (SyntheticField& f : fields) {
        if (f.name == name) return &f;
    }
    return nullptr;
}

bool remove_field(std::vector<SyntheticField>& fields, const std::string& name) {
    auto it = std::find_if(fields.begin(), fields.end(), [&](const SyntheticField& f) { return f.name == name; });
    if (it == fields.end()) return false;
    fields.erase(it);
    return true;
}

TensorFileWriter make_synthetic_rgl(const SyntheticRglSpec& spec) {
    return to_writer(synthetic_rgl_fields(spec));
}

std::string write_synthetic_rgl(const SyntheticRglSpec& spec, const std::string& path) {
    make_synthetic_rgl(spec).write(path);
    return path;
}

namespace {
// Folders handed out by temporary_folder, removed when the test process exits.
struct FolderRegistry {
    std::mutex mutex;
    std::vector<std::string> folders;
    ~FolderRegistry() {
        if (std::getenv("NPF_KEEP_TEST_FILES")) return;
        for (const std::string& f : folders) {
            std::error_code ec;
            std::filesystem::remove_all(f, ec);
        }
    }
};
FolderRegistry& folder_registry() {
    static FolderRegistry registry;
    return registry;
}
}  // namespace

std::string temporary_folder(const std::string& tag) {
    const char* env = std::getenv("TMPDIR");
    std::string root = env && *env ? env : "/tmp";
    while (root.size() > 1 && root.back() == '/') root.pop_back();
    std::string safe;
    for (char ch : tag) {
        const bool ok = (ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') || (ch >= '0' && ch <= '9') ||
                        ch == '-' || ch == '_' || ch == '.';
        safe += ok ? ch : '_';
    }
    if (safe.empty()) safe = "test";
    std::string pattern = root + "/npf-" + safe + "-XXXXXX";
    std::vector<char> buf(pattern.begin(), pattern.end());
    buf.push_back('\0');
    if (!::mkdtemp(buf.data())) {
        throw npf::Error(pattern, std::string("cannot create temporary folder: ") + std::strerror(errno));
    }
    FolderRegistry& registry = folder_registry();
    std::lock_guard<std::mutex> lock(registry.mutex);
    registry.folders.emplace_back(buf.data());
    return registry.folders.back();
}

std::string shared_data_file(const std::string& relative) {
    const char* env = std::getenv("NPF_SHARED_DATA");
    std::string dir = env && *env ? env : NPF_SHARED_DATA_DIR;
    if (dir.empty()) return "";
    std::string path = dir + (dir.back() == '/' ? "" : "/") + relative;
    struct stat st;
    if (::stat(path.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) return "";
    return path;
}

}  // namespace npf::testing
