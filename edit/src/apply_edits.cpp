#include <npf/edit/recipe.h>

#include "history.h"
#include "tables.h"

#include <npf/edit/colour_edits.h>
#include <npf/edit/compression.h>
#include <npf/core/error.h>
#include <npf/shading/npf_albedo.h>
#include <npf/shading/npf_texture_file.h>
#include <npf/core/number_text.h>

namespace npf::edit {

namespace {

// Whether two models shade alike: every table the value reads, the detail layer and the channels
// included (a step that changed only those must have its albedo measured again).
bool same_factors(const NpfModel& a, const NpfModel& b) {
    const auto same_basis = [](const SpectralBasis& x, const SpectralBasis& y) {
        return x.rank == y.rank && x.cells == y.cells && x.basis == y.basis && x.weights == y.weights;
    };
    return a.channels.is_rgb() == b.channels.is_rgb() && a.channels.wavelengths() == b.channels.wavelengths() &&
           a.d_theta == b.d_theta && a.d_phi == b.d_phi && a.g_theta == b.g_theta && a.g_phi == b.g_phi &&
           a.f_theta == b.f_theta && a.rho_d == b.rho_d && a.rho_s == b.rho_s && a.F == b.F && same_basis(a.D, b.D) &&
           same_basis(a.G, b.G) && a.detail_grid == b.detail_grid && same_basis(a.detail, b.detail);
}

}  // namespace

EditResult apply_edits(const NpfModel& model, const std::vector<EditStep>& steps, const EditOptions& options,
                       const std::function<void(std::size_t, const EditRecord&)>& on_step) {
    EditResult r;
    r.model = model;
    int next = detail::next_history_number(model);
    if (options.check_albedo) r.input_albedo = r.output_albedo = npf_largest_albedo(model, options.albedo);
    const double limit = 1.0 + options.albedo_tolerance;
    for (std::size_t i = 0; i < steps.size(); ++i) {
        const EditStep& s = steps[i];
        EditRecord rec;
        const NpfModel before = r.model;
        try {
            if (!s.operation) throw Error(s.origin.empty() ? "edit" : s.origin, "the step '" + s.label + "' has no operation");
            r.model = s.operation(r.model, options, &rec);
        } catch (const Error& e) {
            if (s.origin.empty()) throw;
            throw Error(s.origin, e.what());
        }
        if (options.check_albedo) {
            // An edit that changed nothing (an identity) keeps the last measurement.
            const AlbedoPeak a = same_factors(before, r.model) ? r.output_albedo : npf_largest_albedo(r.model, options.albedo);
            const std::string where = "theta_i " + number_text(a.theta_deg, 3) + " deg, phi_i " + number_text(a.phi_deg, 3) +
                                      " deg, channel " + std::to_string(a.channel);
            rec.summary += "; largest directional albedo " + number_text(a.max, 4) + " (" + where + ")";
            // A warning when this step takes the albedo above the limit, or, where the material
            // already exceeded it (a fit gaining light at grazing views), raises it by more than
            // the tolerance again: a step that leaves a known excess alone is not blamed for it.
            const double previous = r.output_albedo.max;
            if (a.max > limit && (previous <= limit || a.max > previous + options.albedo_tolerance)) {
                std::string w = "the directional albedo reaches " + number_text(a.max, 4) + " (" + where +
                                "): the material reflects more light than it receives";
                if (r.input_albedo.max > limit) w += " (the input already reached " + number_text(r.input_albedo.max, 4) + ")";
                rec.warnings.push_back(w);
            }
            r.output_albedo = a;
        }
        std::string value = s.label + ": " + rec.summary;
        for (const std::string& w : rec.warnings) value += "; WARNING: " + w;
        const std::string key = detail::history_key(next++);
        r.model.metadata.emplace_back(key, value);
        r.history_keys.push_back(key);
        r.records.push_back(rec);
        if (on_step) on_step(i, rec);
    }
    if (!options.description.empty()) {
        bool found = false;
        for (auto& kv : r.model.metadata) {
            if (kv.first == "description") kv.second = options.description, found = true;
        }
        if (!found) r.model.metadata.emplace_back("description", options.description);
    }
    return r;
}

}  // namespace npf::edit
