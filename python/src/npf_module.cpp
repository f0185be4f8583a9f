// npf._npf: the Python package's compiled half (nanobind). Thin: every call is one of the
// libraries' (open_material, convert_material, edit::apply_edits, the batched closure through
// MaterialArrays); python/npf/__init__.py shapes the arguments (numpy arrays, keyword settings)
// and documents the API. npf::Error becomes npf.Error, with the file and the problem.
#include "material_arrays.h"

#include <npf/converter/convert.h>
#include <npf/converter/convert_settings_table.h>
#include <npf/materials/open_material.h>
#include <npf/core/atomic_file.h>
#include <npf/core/error.h>
#include <npf/core/float_environment.h>
#include <npf/core/version.h>
#include <npf/edit/edit_request.h>
#include <npf/shading/half_vector_sampler.h>
#include <npf/shading/npf_texture_file.h>

#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/optional.h>
#include <nanobind/stl/pair.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/tuple.h>
#include <nanobind/stl/vector.h>

#include <algorithm>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace nb = nanobind;
using namespace nb::literals;

namespace npf::python {

namespace {

using Rows3 = nb::ndarray<const double, nb::shape<-1, 3>, nb::c_contig, nb::device::cpu>;
using Rows2 = nb::ndarray<const double, nb::shape<-1, 2>, nb::c_contig, nb::device::cpu>;
using WavelengthRows = nb::ndarray<const float, nb::ndim<2>, nb::c_contig, nb::device::cpu>;
using Array = nb::ndarray<nb::numpy, double>;

PyObject* g_error_type = nullptr;

// A new numpy array of doubles that owns its memory.
Array new_array(std::initializer_list<std::size_t> shape, double*& data) {
    std::size_t size = 1;
    for (std::size_t s : shape) size *= s;
    data = new double[std::max<std::size_t>(size, 1)];  // every element is written
    nb::capsule owner(data, [](void* p) noexcept { delete[] static_cast<double*>(p); });
    return Array(data, shape.size(), shape.begin(), owner);
}

// A new numpy array holding a copy of `values` (floats or indices), of the given shape.
template <class T>
nb::ndarray<nb::numpy, T> copy_array(const std::vector<T>& values, std::initializer_list<std::size_t> shape) {
    T* data = new T[std::max<std::size_t>(values.size(), 1)];
    std::copy(values.begin(), values.end(), data);
    nb::capsule owner(data, [](void* p) noexcept { delete[] static_cast<T*>(p); });
    return nb::ndarray<nb::numpy, T>(data, shape.size(), shape.begin(), owner);
}

// A spectral basis as {"rank", "basis" [rank][cells], "weights" [channels][rank]}.
nb::dict basis_dict(const SpectralBasis& s, std::size_t channels) {
    nb::dict d;
    d["rank"] = s.rank;
    d["basis"] = copy_array(s.basis, {std::size_t(s.rank), s.cells});
    d["weights"] = copy_array(s.weights, {channels, std::size_t(s.rank)});
    return d;
}

// The wavelengths of a call: none, one row shared by every pair, or a row per pair.
ArrayWavelengths wavelengths_of(const std::optional<WavelengthRows>& nm, bool per_pair) {
    if (!nm) return {};
    return {nm->data(), nm->shape(1), per_pair};
}

class PyMaterial {
public:
    explicit PyMaterial(const std::string& path) : m_arrays(path) {}

    nb::dict info() const {
        const BrdfInfo& i = m_arrays.brdf().info();
        nb::dict d;
        d["path"] = i.path;
        d["format"] = i.format;
        d["description"] = i.description;
        d["isotropic"] = i.isotropic;
        d["channels"] = i.channels.is_rgb() ? "rgb" : "spectral";
        std::vector<std::string> names;
        for (std::size_t k = 0; k < i.channels.size(); ++k) names.push_back(i.channels.name(k));
        d["channel_names"] = names;
        d["wavelengths_nm"] = i.channels.wavelengths();
        d["file_bytes"] = i.file_bytes;
        d["details"] = i.details;
        d["batched"] = m_arrays.closure() != nullptr;
        return d;
    }

    Array eval(const Rows3& wi, const Rows3& wo, const std::optional<WavelengthRows>& nm, bool per_pair, bool cos,
               int threads) const {
        const ArrayWavelengths w = wavelengths_of(nm, per_pair);
        const std::size_t n = wi.shape(0), count = m_arrays.value_count(w, n);
        double* out = nullptr;
        Array result = new_array({n, count}, out);
        nb::gil_scoped_release release;
        m_arrays.eval(n, wi.data(), wo.data(), w, cos, out, threads);
        return result;
    }

    Array pdf(const Rows3& wi, const Rows3& wo, int threads) const {
        const std::size_t n = wi.shape(0);
        double* out = nullptr;
        Array result = new_array({n}, out);
        nb::gil_scoped_release release;
        m_arrays.pdf(n, wi.data(), wo.data(), out, threads);
        return result;
    }

    std::tuple<Array, Array, Array> sample(const Rows3& wi, const Rows2& u, const std::optional<WavelengthRows>& nm,
                                           bool per_pair, int threads) const {
        const ArrayWavelengths w = wavelengths_of(nm, per_pair);
        const std::size_t n = wi.shape(0), count = m_arrays.value_count(w, n);
        double *wo = nullptr, *pdf = nullptr, *weight = nullptr;
        Array wo_array = new_array({n, 3}, wo), pdf_array = new_array({n}, pdf), weight_array = new_array({n, count}, weight);
        {
            nb::gil_scoped_release release;
            m_arrays.sample(n, wi.data(), u.data(), w, wo, pdf, weight, threads);
        }
        return {wo_array, pdf_array, weight_array};
    }

    // The factor texture's tables as the closure shades with them, and its sampler's, for
    // renderers that evaluate the model themselves (the traced Mitsuba plugin, npf/mitsuba.py):
    // one reader, npf's. The sampler is rebuilt from the model as the closure builds its own
    // (HalfVectorSampler's public constructor, the same tables to the bit).
    nb::dict factor_tables() const {
        const NpfClosure* closure = m_arrays.closure();
        if (!closure) {
            throw Error(m_arrays.brdf().info().path, "is not an NPF factor texture; its tables exist only for a conversion (npf convert)");
        }
        const NpfModel& m = closure->model();
        const std::size_t C = m.channel_count();
        nb::dict d;
        d["channels"] = m.channels.is_rgb() ? "rgb" : "spectral";
        d["wavelengths_nm"] = copy_array(m.channels.wavelengths(), {m.channels.wavelengths().size()});
        d["d_theta"] = m.d_theta, d["d_phi"] = m.d_phi, d["f_theta"] = m.f_theta;
        d["g_theta"] = m.g_theta, d["g_phi"] = m.g_phi;
        d["rho_d"] = copy_array(m.rho_d, {C});
        d["rho_s"] = copy_array(m.rho_s, {C});
        d["F"] = copy_array(m.F, {C, std::size_t(m.f_theta)});
        d["D"] = basis_dict(m.D, C);
        d["G"] = basis_dict(m.G, C);
        if (m.has_detail()) {
            d["detail_grid"] = nb::make_tuple(m.detail_grid.theta_h, m.detail_grid.theta_d, m.detail_grid.phi_d);
            d["detail"] = basis_dict(m.detail, C);
        }
        d["diffuse_probability"] = closure->diffuse_probability();
        if (closure->diffuse_probability() < 1.0) {
            const ExactFloatScope exact;
            const HalfVectorSampler sampler(HalfVectorSampler::luminance_averaged_ndf(m), m.d_theta, m.d_phi);
            const std::vector<AliasTable::Bin>& bins = sampler.cells().bins();
            std::vector<float> keep(bins.size()), density(bins.size());
            std::vector<std::uint32_t> alias(bins.size());
            for (std::size_t i = 0; i < bins.size(); ++i) {
                keep[i] = bins[i].keep;
                alias[i] = bins[i].alias;
                // The solid-angle density of a half vector in cell i: HalfVectorSampler::pdf's product.
                density[i] = float(double(bins[i].pmf) * sampler.inv_solid_angle()[i / std::size_t(m.d_phi)]);
            }
            nb::dict s;
            s["keep"] = copy_array(keep, {keep.size()});
            s["alias"] = copy_array(alias, {alias.size()});
            s["density"] = copy_array(density, {density.size()});
            s["half_sin2"] = copy_array(sampler.half_sin2(), {sampler.half_sin2().size()});
            d["sampler"] = s;
        }
        return d;
    }

private:
    MaterialArrays m_arrays;
};

nb::dict error_dict(const BrdfSpaceError& e) {
    nb::dict d;
    d["mean_relative_rms"] = e.mean_relative_rms;
    d["max_relative_rms"] = e.max_relative_rms;
    return d;
}

// npf convert, from (key, text) settings: the batch configuration's keys and values
// (convert_settings_table.h), so that a setting means what it means on the command line.
nb::dict convert(const std::string& input, const std::string& output,
                 const std::vector<std::pair<std::string, std::string>>& settings, const nb::object& progress) {
    const ConvertSettingsTable& table = convert_settings_table();
    std::vector<std::optional<SettingValue>> given(table.size());
    for (const auto& [key, text] : settings) {
        const ConvertSettingRow* row = find_setting(table, key);
        if (!row) throw Error(key, "not a conversion setting (npf convert --help lists them; use the batch keys, e.g. error_pairs)");
        given[std::size_t(row - table.data())] = check_setting(*row, text, key);
    }
    ConvertReport r;
    {
        nb::gil_scoped_release release;
        const std::unique_ptr<Brdf> source = open_material(input);
        ConvertSettings s = resolve_convert_settings(
            table, [&](const ConvertSettingRow& row) { return given[std::size_t(&row - table.data())]; },
            [](const ConvertSettingRow& row) { return row.key; }, source->info().isotropic);
        check_output_path(output);
        // Each progress report also looks for Ctrl-C (a conversion can take minutes): the
        // KeyboardInterrupt unwinds the conversion, which then publishes nothing.
        const std::function<void(double)> report_progress = [&progress](double f) {
            nb::gil_scoped_acquire acquire;
            if (PyErr_CheckSignals() != 0) throw nb::python_error();
            if (!progress.is_none()) progress(f);
        };
        r = convert_material(*source, output, s, report_progress);
    }
    nb::dict d;
    d["output"] = output;
    d["isotropic"] = r.isotropic;
    d["channel_count"] = r.channels.size();
    d["d_rank"] = r.d_rank;
    d["g_rank"] = r.g_rank;
    d["input_bytes"] = r.input_bytes;
    d["output_bytes"] = r.output_bytes;
    d["error"] = error_dict(r.compressed_error);
    d["has_detail"] = r.has_detail;
    if (r.has_detail) d["error_with_detail"] = error_dict(r.detailed_error);
    d["albedo_max"] = r.albedo_max;
    d["energy_error"] = r.energy_error;
    if (r.predicted) {
        d["predicted_psnr_db"] = r.prediction.psnr;
        d["predicted_floor_db"] = r.prediction.floor_psnr;
        // Each lighting of the set (predicted_psnr_db is their worst): {name: (psnr, floor)}.
        nb::dict each;
        for (const LightingPrediction& l : r.prediction.lightings) each[l.lighting.c_str()] = nb::make_tuple(l.psnr, l.floor_psnr);
        d["predicted_psnr_by_lighting"] = each;
    }
    d["seconds"] = r.seconds;
    d["peak_memory_gib"] = r.peak_memory_gib;
    return d;
}

// npf edit, from a recipe (may be empty) and (flag, text) pairs in order (edit_request.h).
nb::dict edit(const std::string& input, const std::string& output, const std::string& recipe,
              const std::vector<std::pair<std::string, std::string>>& flags, bool dry_run) {
    std::vector<std::string> summaries, warnings;
    edit::EditResult result;
    {
        nb::gil_scoped_release release;
        edit::EditRequest request = edit::edit_request(recipe, flags);
        edit::require_npf_textures(input, request);
        if (!dry_run) check_output_path(output);
        const NpfModel model = read_npf_texture(input);
        result = edit::apply_edits(model, request.steps, request.options, [&](std::size_t i, const edit::EditRecord& r) {
            summaries.push_back(request.steps[i].label + ": " + r.summary);
            for (const std::string& w : r.warnings) warnings.push_back("step " + std::to_string(i + 1) + ": " + w);
        });
        if (!dry_run) write_npf_texture(result.model, output);
    }
    nb::dict d;
    d["output"] = dry_run ? std::string() : output;
    d["steps"] = summaries;
    d["warnings"] = warnings;
    d["history"] = result.history_keys;
    d["albedo_max"] = result.output_albedo.max;
    d["input_albedo_max"] = result.input_albedo.max;
    return d;
}

std::vector<std::pair<std::string, bool>> convert_setting_keys() {
    std::vector<std::pair<std::string, bool>> keys;
    for (const ConvertSettingRow& row : convert_settings_table()) keys.emplace_back(row.key, row.kind == SettingKind::Switch);
    return keys;
}

std::vector<std::pair<std::string, bool>> edit_flags() {
    std::vector<std::pair<std::string, bool>> flags;
    for (const edit::EditRunFlag& f : edit::edit_run_flags()) flags.emplace_back(f.name, f.takes_value);
    return flags;
}

}  // namespace

}  // namespace npf::python

NB_MODULE(_npf, m) {
    using namespace npf::python;
    m.doc() = "npf's compiled core; use the npf package (python/npf/__init__.py)";
    m.attr("__version__") = npf::version();
    // Materials held by other extensions at exit (a Mitsuba scene's npf BSDFs) are freed after
    // this module's types: nanobind would report them as leaks, which they are not.
    nb::set_leak_warnings(false);

    g_error_type = PyErr_NewExceptionWithDoc("npf.Error",
                                             "A bad file, setting or input: .source names it, .problem says what is wrong.",
                                             PyExc_RuntimeError, nullptr);
    m.attr("Error") = nb::handle(g_error_type);
    nb::register_exception_translator([](const std::exception_ptr& p, void*) {
        try {
            std::rethrow_exception(p);
        } catch (const npf::Error& e) {
            nb::object error = nb::handle(g_error_type)(nb::str(e.what()));
            nb::setattr(error, "source", nb::str(e.source().c_str()));
            nb::setattr(error, "problem", nb::str(e.problem().c_str()));
            PyErr_SetObject(g_error_type, error.ptr());
        }
    });

    nb::class_<PyMaterial>(m, "_Material")
        .def(nb::init<const std::string&>(), "path"_a)
        .def("info", &PyMaterial::info)
        .def("eval", &PyMaterial::eval, "wi"_a, "wo"_a, "nm"_a.none(), "per_pair"_a, "cos"_a, "threads"_a)
        .def("pdf", &PyMaterial::pdf, "wi"_a, "wo"_a, "threads"_a)
        .def("sample", &PyMaterial::sample, "wi"_a, "u"_a, "nm"_a.none(), "per_pair"_a, "threads"_a)
        .def("factor_tables", &PyMaterial::factor_tables);
    m.def("convert", &convert, "input"_a, "output"_a, "settings"_a, "progress"_a.none());
    m.def("edit", &edit, "input"_a, "output"_a, "recipe"_a, "flags"_a, "dry_run"_a);
    m.def("convert_setting_keys", &convert_setting_keys);
    m.def("edit_flags", &edit_flags);
}
