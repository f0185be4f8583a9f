// MERL `.binary` reader. The Nearest lookup repeats the reference reader (BRDFRead.cpp,
// Matusik et al.) operation for operation in double, including its vector rotations, so that
// bin choices agree with it even at bin edges and for in-plane configurations, where the sign
// of a zero decides between the first and last phi_d bin.
#include <npf/core/text.h>
#include <npf/materials/merl_brdf.h>

#include <npf/core/error.h>
#include <npf/core/input_file.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <system_error>

namespace npf {

namespace {

constexpr std::size_t kHeaderBytes = 12;
constexpr int kChannelCount = 3;
constexpr double kChannelScale[kChannelCount] = {kMerlScaleRed, kMerlScaleGreen,
                                                 kMerlScaleBlue};
constexpr const char* kChannelName[kChannelCount] = {"R", "G", "B"};
// The largest table a MERL file may hold: 1 GiB of doubles, thirty times the standard
// 90 x 90 x 180 (35 MB), checked before anything is allocated.
constexpr std::uint64_t kMaxTableBytes = std::uint64_t(1) << 30;

std::uint32_t read_le32(const std::uint8_t* p) {
    return static_cast<std::uint32_t>(p[0]) | (static_cast<std::uint32_t>(p[1]) << 8) |
           (static_cast<std::uint32_t>(p[2]) << 16) | (static_cast<std::uint32_t>(p[3]) << 24);
}

std::int32_t read_le_int32(const std::uint8_t* p) {
    std::uint32_t u = read_le32(p);
    std::int32_t v;
    std::memcpy(&v, &u, sizeof v);
    return v;
}

bool host_is_little_endian() {
    const std::uint16_t probe = 1;
    std::uint8_t first;
    std::memcpy(&first, &probe, 1);
    return first == 1;
}

std::string dims_text(std::int64_t n_th, std::int64_t n_td, std::int64_t n_pd) {
    return std::to_string(n_th) + " x " + std::to_string(n_td) + " x " + std::to_string(n_pd);
}

// Checks dimensions and computes the whole file size they imply. Returns an empty string when
// fine, else the problem.
std::string check_dims(std::int64_t n_th, std::int64_t n_td, std::int64_t n_pd,
                       std::uint64_t& file_bytes) {
    if (n_th <= 0 || n_td <= 0 || n_pd <= 0)
        return "bad dimensions " + dims_text(n_th, n_td, n_pd) +
               " (theta_h x theta_d x phi_d): each must be positive";
    // Keep the byte count, and every index, representable in 64 bits and in size_t.
    const std::uint64_t limit =
        std::min<std::uint64_t>(std::numeric_limits<std::uint64_t>::max(),
                                std::numeric_limits<std::size_t>::max());
    const std::uint64_t max_bins = (limit - kHeaderBytes) / (kChannelCount * sizeof(double));
    const std::uint64_t a = static_cast<std::uint64_t>(n_th);
    const std::uint64_t b = static_cast<std::uint64_t>(n_td);
    const std::uint64_t c = static_cast<std::uint64_t>(n_pd);
    if (a > max_bins / b || a * b > max_bins / c)
        return "bad dimensions " + dims_text(n_th, n_td, n_pd) +
               " (theta_h x theta_d x phi_d): the table would be too large";
    if (a * b * c > kMaxTableBytes / (kChannelCount * sizeof(double)))
        return "bad dimensions " + dims_text(n_th, n_td, n_pd) + " (theta_h x theta_d x phi_d): the table would hold " +
               std::to_string(a * b * c * kChannelCount * sizeof(double)) + " bytes, more than the " +
               std::to_string(kMaxTableBytes >> 20) + " MiB a MERL file may hold";
    file_bytes = kHeaderBytes + a * b * c * kChannelCount * sizeof(double);
    return {};
}

// ---- The reference reader's geometry, operation for operation ----------------------------

void normalize3(double v[3]) {
    double len = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    v[0] = v[0] / len;
    v[1] = v[1] / len;
    v[2] = v[2] / len;
}

void cross3(const double* v1, const double* v2, double* out) {
    out[0] = v1[1] * v2[2] - v1[2] * v2[1];
    out[1] = v1[2] * v2[0] - v1[0] * v2[2];
    out[2] = v1[0] * v2[1] - v1[1] * v2[0];
}

// Rodrigues rotation of `vector` about the unit `axis` by `angle`.
void rotate_vector(const double* vector, const double* axis, double angle, double* out) {
    double cos_ang = std::cos(angle);
    double sin_ang = std::sin(angle);
    out[0] = vector[0] * cos_ang;
    out[1] = vector[1] * cos_ang;
    out[2] = vector[2] * cos_ang;
    double temp = axis[0] * vector[0] + axis[1] * vector[1] + axis[2] * vector[2];
    temp = temp * (1.0 - cos_ang);
    out[0] += axis[0] * temp;
    out[1] += axis[1] * temp;
    out[2] += axis[2] * temp;
    double cross[3];
    cross3(axis, vector, cross);
    out[0] += cross[0] * sin_ang;
    out[1] += cross[1] * sin_ang;
    out[2] += cross[2] * sin_ang;
}

// acos that cannot return NaN: rounding can push a normalised component just past 1.
double safe_acos(double x) { return std::acos(std::clamp(x, -1.0, 1.0)); }

// Angle from the z axis that stays accurate near it (acos(z) loses half the digits there).
double robust_polar_angle(const double v[3]) {
    return std::atan2(std::sqrt(v[0] * v[0] + v[1] * v[1]), v[2]);
}

struct HalfDiff {
    double theta_h = 0, phi_h = 0, theta_d = 0, phi_d = 0;
};

// Rusinkiewicz coordinates of (in, out). `reference_angles` uses the reference reader's acos;
// otherwise the polar angles come from atan2, which Linear needs near the normal where the
// sqrt-mapped theta_h coordinate magnifies angle errors.
HalfDiff half_diff(const double in_vec[3], const double out_vec[3], bool reference_angles) {
    double in[3] = {in_vec[0], in_vec[1], in_vec[2]};
    normalize3(in);
    // As in the reference: the half vector is formed from the vectors as given.
    double half[3] = {(in_vec[0] + out_vec[0]) / 2.0, (in_vec[1] + out_vec[1]) / 2.0,
                      (in_vec[2] + out_vec[2]) / 2.0};
    normalize3(half);

    HalfDiff hd;
    hd.theta_h = reference_angles ? safe_acos(half[2]) : robust_polar_angle(half);
    hd.phi_h = std::atan2(half[1], half[0]);

    const double bi_normal[3] = {0.0, 1.0, 0.0};
    const double normal[3] = {0.0, 0.0, 1.0};
    double temp[3], diff[3];
    rotate_vector(in, normal, -hd.phi_h, temp);
    rotate_vector(temp, bi_normal, -hd.theta_h, diff);

    hd.theta_d = reference_angles ? safe_acos(diff[2]) : robust_polar_angle(diff);
    hd.phi_d = std::atan2(diff[1], diff[0]);
    return hd;
}

// The three index functions keep the reference's arithmetic; the only additions are that NaN
// and out-of-range values map to the end bins instead of undefined int conversions.
int to_bin(double scaled, int n) {
    if (!(scaled > 0.0)) return 0;
    if (!(scaled < n)) return n - 1;
    return std::min(static_cast<int>(scaled), n - 1);
}

int theta_half_index(double theta_half, int n) {
    if (!(theta_half > 0.0)) return 0;
    double theta_half_deg = ((theta_half / (kPiD / 2.0)) * n);
    return to_bin(std::sqrt(theta_half_deg * n), n);
}

int theta_diff_index(double theta_diff, int n) { return to_bin(theta_diff / (kPiD * 0.5) * n, n); }

// Reciprocity: the table is unchanged under phi_d -> phi_d + pi, so it only covers [0, pi).
double fold_phi_diff(double phi_diff) { return phi_diff < 0.0 ? phi_diff + kPiD : phi_diff; }

int phi_diff_index(double phi_diff, int n) { return to_bin(fold_phi_diff(phi_diff) / kPiD * n, n); }

// ---- Linear lookup helpers -------------------------------------------------------------

struct AxisBlend {
    int i0 = 0, i1 = 0;
    double w1 = 0.0;  // weight of i1
};

// `coord` in bin units (bin k covers [k, k+1)); blends the two nearest bin centres and holds
// the end bins' values beyond the outer centres.
AxisBlend clamped_blend(double coord, int n) {
    if (!std::isfinite(coord)) coord = 0.0;
    double t = std::clamp(coord - 0.5, 0.0, static_cast<double>(n - 1));
    AxisBlend b;
    b.i0 = std::min(static_cast<int>(t), n - 1);
    b.i1 = std::min(b.i0 + 1, n - 1);
    b.w1 = b.i1 == b.i0 ? 0.0 : t - b.i0;
    return b;
}

// Like clamped_blend, but periodic: phi_d is periodic with period pi after the reciprocity
// fold, so the last and first bins are neighbours. Clamping there would make a jump at every
// in-plane configuration (phi_d = 0 = pi), where rounding picks the side.
AxisBlend periodic_blend(double coord, int n) {
    if (!std::isfinite(coord)) coord = 0.0;
    double t = coord - 0.5;
    double base = std::floor(t);
    AxisBlend b;
    b.w1 = std::clamp(t - base, 0.0, 1.0);
    long long i = static_cast<long long>(base) % n;
    if (i < 0) i += n;
    b.i0 = static_cast<int>(i);
    b.i1 = (b.i0 + 1) % n;
    return b;
}

}  // namespace

// ---- Loading -----------------------------------------------------------------------------

bool MerlBrdf::has_plausible_header(const std::uint8_t* head, std::size_t head_size, std::uint64_t file_size) {
    if (head == nullptr || head_size < kHeaderBytes) return false;
    const std::int32_t n_th = read_le_int32(head), n_td = read_le_int32(head + 4), n_pd = read_le_int32(head + 8);
    if (n_th == 90 && n_td == 90 && n_pd == 180) return true;  // MERL's own table
    std::uint64_t expected = 0;
    if (!check_dims(n_th, n_td, n_pd, expected).empty()) return false;
    // Three positive dimensions whose table is within a factor of two of the file's size: random
    // bytes rarely do that, a MERL file cut short or padded does.
    return expected / 2 <= file_size && file_size / 2 <= expected;
}

bool MerlBrdf::looks_like_merl(const std::uint8_t* head, std::size_t head_size,
                               std::uint64_t file_size) {
    if (head == nullptr || head_size < kHeaderBytes) return false;
    std::uint64_t expected = 0;
    if (!check_dims(read_le_int32(head), read_le_int32(head + 4), read_le_int32(head + 8),
                    expected)
             .empty())
        return false;
    return expected == file_size;
}

std::unique_ptr<MerlBrdf> MerlBrdf::load(const std::string& path, MerlOptions opts) {
    const std::uint64_t file_size = require_regular_file(path, "a MERL file");
    if (file_size == 0) throw Error(path, "file is empty");

    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(path, "cannot open file for reading");
    if (file_size < kHeaderBytes)
        throw Error(path, "truncated: the file has " + std::to_string(file_size) +
                              " bytes, a MERL header needs 12");

    std::uint8_t header[kHeaderBytes];
    in.read(reinterpret_cast<char*>(header), kHeaderBytes);
    if (!in) throw Error(path, "read error in the header");
    const std::int32_t n_th = read_le_int32(header);
    const std::int32_t n_td = read_le_int32(header + 4);
    const std::int32_t n_pd = read_le_int32(header + 8);

    std::uint64_t expected_size = 0;
    std::string problem = check_dims(n_th, n_td, n_pd, expected_size);
    if (!problem.empty()) throw Error(path, problem);
    if (file_size != expected_size) {
        const std::string sizes = "the header's " + dims_text(n_th, n_td, n_pd) +
                                  " table needs " + std::to_string(expected_size) +
                                  " bytes, the file has " + std::to_string(file_size);
        if (file_size < expected_size) throw Error(path, "truncated: " + sizes);
        throw Error(path, "size mismatch: " + sizes + " (trailing data)");
    }

    auto brdf = std::unique_ptr<MerlBrdf>(new MerlBrdf());
    brdf->m_lookup = opts.lookup;
    brdf->m_n_th = n_th;
    brdf->m_n_td = n_td;
    brdf->m_n_pd = n_pd;
    brdf->m_bins = static_cast<std::size_t>(n_th) * static_cast<std::size_t>(n_td) *
                   static_cast<std::size_t>(n_pd);
    const std::size_t value_count = brdf->m_bins * kChannelCount;
    std::vector<double>& fr = brdf->m_fr;
    fr.resize(value_count);
    in.read(reinterpret_cast<char*>(fr.data()),
            static_cast<std::streamsize>(value_count * sizeof(double)));
    if (!in || static_cast<std::size_t>(in.gcount()) != value_count * sizeof(double))
        throw Error(path, "truncated: read failed inside the table");

    if (!host_is_little_endian()) {
        for (double& v : fr) {
            std::uint8_t bytes[8];
            std::memcpy(bytes, &v, 8);
            std::reverse(bytes, bytes + 8);
            std::memcpy(&v, bytes, 8);
        }
    }

    for (int c = 0; c < kChannelCount; ++c) {
        double* channel = fr.data() + c * brdf->m_bins;
        for (std::size_t i = 0; i < brdf->m_bins; ++i) {
            const double stored = channel[i];
            // The same product as the reference reader (brdf[ind] * SCALE), done once here.
            const double value = stored * kChannelScale[c];
            if (!std::isfinite(stored) || std::fabs(value) > kMaxMaterialValue) {
                const std::size_t ipd = i % n_pd, itd = (i / n_pd) % n_td,
                                  ith = i / (static_cast<std::size_t>(n_pd) * n_td);
                throw Error(path, std::string(std::isfinite(stored) ? "out-of-range value "
                                                                    : "non-finite value ") +
                                      "in channel " + kChannelName[c] + " at index " +
                                      std::to_string(i) + " (theta_h " + std::to_string(ith) +
                                      ", theta_d " + std::to_string(itd) + ", phi_d " +
                                      std::to_string(ipd) + ")");
            }
            channel[i] = value;
        }
    }

    std::size_t invalid_bins = 0;
    for (std::size_t i = 0; i < brdf->m_bins; ++i) {
        if (fr[i] < 0.0 || fr[i + brdf->m_bins] < 0.0 || fr[i + 2 * brdf->m_bins] < 0.0)
            ++invalid_bins;
    }

    // f_r is a (trilinear) interpolation of the table, so its largest |value| bounds f_r and
    // with it f_r cos(theta_i) cos(theta_o); each value is already under the cap.
    double largest = 0.0;
    for (double v : fr) largest = std::max(largest, std::fabs(v));
    brdf->describe_rgb_file("merl", path, file_size);
    BrdfInfo& info = brdf->m_info;
    info.value_bound = largest;
    info.details = {
        {"grid", dims_text(n_th, n_td, n_pd) + " (theta_h x theta_d x phi_d)"},
        {"lookup", opts.lookup == MerlLookup::Nearest ? "nearest" : "linear"},
        {"channel scales", "R 1/1500, G 1.15/1500, B 1.66/1500"},
        {"invalid samples",
         std::to_string(invalid_bins) + " of " + std::to_string(brdf->m_bins)},
    };
    return brdf;
}

double MerlBrdf::bin_value(int channel, int ith, int itd, int ipd) const {
    return m_fr[static_cast<std::size_t>(channel) * m_bins + bin_index(ith, itd, ipd)];
}

// ---- Evaluation --------------------------------------------------------------------------

void MerlBrdf::lookup_nearest(const double in[3], const double out[3], double rgb[3]) const {
    const HalfDiff hd = half_diff(in, out, /*reference_angles=*/true);
    const std::size_t index =
        bin_index(theta_half_index(hd.theta_h, m_n_th), theta_diff_index(hd.theta_d, m_n_td),
                  phi_diff_index(hd.phi_d, m_n_pd));
    for (int c = 0; c < kChannelCount; ++c) rgb[c] = m_fr[c * m_bins + index];
}

void MerlBrdf::lookup_linear(const double in[3], const double out[3], double rgb[3]) const {
    const HalfDiff hd = half_diff(in, out, /*reference_angles=*/false);
    // Continuous versions of the reference's bin coordinates (bin k covers [k, k+1)).
    const AxisBlend bh =
        clamped_blend(std::sqrt(std::max(hd.theta_h, 0.0) / (kPiD / 2.0)) * m_n_th, m_n_th);
    const AxisBlend bd = clamped_blend(hd.theta_d / (kPiD / 2.0) * m_n_td, m_n_td);
    const AxisBlend bp = periodic_blend(fold_phi_diff(hd.phi_d) / kPiD * m_n_pd, m_n_pd);

    // Invalid (negative) bins are left out and the valid corners' weights renormalised, so the
    // sentinel values do not bleed into measured ones; only where every corner with weight is
    // invalid does the (negative) blend of all corners come out.
    double valid_sum[kChannelCount] = {0, 0, 0}, valid_weight[kChannelCount] = {0, 0, 0};
    double all_sum[kChannelCount] = {0, 0, 0};
    for (int corner = 0; corner < 8; ++corner) {
        const bool h1 = corner & 1, d1 = corner & 2, p1 = corner & 4;
        const double w = (h1 ? bh.w1 : 1.0 - bh.w1) * (d1 ? bd.w1 : 1.0 - bd.w1) *
                         (p1 ? bp.w1 : 1.0 - bp.w1);
        if (w <= 0.0) continue;
        const std::size_t index =
            bin_index(h1 ? bh.i1 : bh.i0, d1 ? bd.i1 : bd.i0, p1 ? bp.i1 : bp.i0);
        for (int c = 0; c < kChannelCount; ++c) {
            const double v = m_fr[c * m_bins + index];
            all_sum[c] += w * v;
            if (v >= 0.0) {
                valid_sum[c] += w * v;
                valid_weight[c] += w;
            }
        }
    }
    for (int c = 0; c < kChannelCount; ++c)
        rgb[c] = valid_weight[c] > 0.0 ? valid_sum[c] / valid_weight[c] : all_sum[c];
}

void MerlBrdf::eval_cos(const Vec3& wi, const Vec3& wo, const ChannelQuery& query,
                        float* out) const {
    if (!evaluable(wi, wo, query, out)) return;
    const double in[3] = {wi.x, wi.y, wi.z};
    const double outv[3] = {wo.x, wo.y, wo.z};
    double rgb[kChannelCount];
    if (m_lookup == MerlLookup::Nearest)
        lookup_nearest(in, outv, rgb);
    else
        lookup_linear(in, outv, rgb);

    write_rgb_query(rgb, double(wo.z), query, out);  // in double: Nearest is the reference reader's bins
}

}  // namespace npf
