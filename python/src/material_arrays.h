// Any material (npf::open_material) evaluated over arrays of direction pairs, as the Python
// package hands them over: eval, pdf and sample of N pairs at once. A factor texture shades
// through the closure's batched calls (npf_batch.h); any other source (a measurement, a recipe,
// a network) pair by pair through npf::Brdf. Either way the work runs in fixed chunks on npf's
// threads (npf/core/parallel.h), so results do not depend on the thread count, and the numbers
// are those `npf eval` prints for the same pairs (directions read by npf::unit_direction).
#pragma once

#include <npf/core/brdf.h>
#include <npf/shading/npf_closure.h>

#include <cstddef>
#include <memory>
#include <string>

namespace npf::python {

// Wavelengths for a call: none (the stored channels), `count` shared by every pair, or `count`
// per pair (nm[i * count + k]), in nanometres.
struct ArrayWavelengths {
    const float* nm = nullptr;
    std::size_t count = 0;
    bool per_pair = false;
};

class MaterialArrays {
public:
    // Throws npf::Error naming the file (open_material).
    explicit MaterialArrays(const std::string& path);

    const Brdf& brdf() const { return *m_brdf; }
    // The closure a factor texture shades through (memory path), or null for other sources.
    const NpfClosure* closure() const { return m_closure; }

    // Values per pair for `wavelengths` over n pairs; throws npf::Error for wavelengths an RGB
    // file cannot give and for any that is not a positive finite number.
    std::size_t value_count(const ArrayWavelengths& wavelengths, std::size_t n) const;

    // wi, wo: n x 3 doubles (row-major), wi the direction the query is conditioned on (npf::Brdf's
    // convention, docs/conventions.md). out: n x value_count doubles, f_r in 1/sr (f_r cos theta_o
    // with `cos`). Throws npf::Error naming the row of a direction of zero length or with NaN.
    void eval(std::size_t n, const double* wi, const double* wo, const ArrayWavelengths& wavelengths, bool cos,
              double* out, int threads) const;
    // out: n densities (1/sr) with which the material samples wo given wi.
    void pdf(std::size_t n, const double* wi, const double* wo, double* out, int threads) const;
    // u: n x 2 uniform numbers in [0, 1). wo_out: n x 3, pdf_out: n, weight_out: n x value_count
    // (f_r cos theta_o / pdf); a pair that draws nothing gets wo 0, pdf 0, weights 0.
    void sample(std::size_t n, const double* wi, const double* u, const ArrayWavelengths& wavelengths, double* wo_out,
                double* pdf_out, double* weight_out, int threads) const;

private:
    std::unique_ptr<Brdf> m_brdf;
    const NpfClosure* m_closure = nullptr;
};

}  // namespace npf::python
