// Neural BRDF networks (`.h5`) as a material format: detection, loader (NbrdfBrdf,
// nbrdf_brdf.cpp) and user documentation.
#include <npf/materials/material_formats.h>
#include <npf/materials/nbrdf_brdf.h>

#include <npf/core/text.h>

namespace npf {

// Any HDF5 file, or any file named like one, is taken for a Neural BRDF network: the reader says
// what is missing (or that it is not HDF5 at all).
MaterialFormat nbrdf_material_format() {
    MaterialFormat f;
    f.described_as = "a Neural BRDF .h5";
    f.claims_file = [](const MaterialFileHead& h) {
        return NbrdfBrdf::has_hdf5_signature(h.bytes, h.count) || ends_with(h.path, ".h5") || ends_with(h.path, ".hdf5");
    };
    f.open = [](const std::string& path) -> std::unique_ptr<Brdf> { return NbrdfBrdf::load(path); };
    f.title = "Neural BRDF networks `.h5` (`npf::NbrdfBrdf`, `materials/src/nbrdf_brdf.cpp`)";
    f.documentation = R"(**Reads** the paper's baseline (Sztrajman et al. 2021): one small network per material, as the
authors publish them (`../shared/data/nbrdf/<material>.h5`, trained from the five RGL files),
recognised by HDF5's signature or a name ending in `.h5` or `.hdf5`. Read with the HDF5 C API
(`libhdf5-dev`); the `.json` beside each file (the Keras model) is not read, since the
architecture it describes is fixed here and its `exp(x) - 1` layer is stored as marshalled Python
bytecode.

- **What is read.** `dense_k/dense_k/kernel:0` (inputs x units, row-major, y = x W + b) and
  `dense_k/dense_k/bias:0` for k = 1, 2, 3, as float (HDF5 converts any stored float type). The
  layer sizes come from the file and must chain 6 -> n1 -> n2 -> 3 (hidden widths 1 to 256; the
  published files are 6 -> 21 -> 21 -> 3, 675 weights); a `dense_4`, a missing dataset, an
  integer dataset, any other shape or a non-finite weight is refused with one line naming the file
  and the dataset. HDF5's own error printing is switched off while reading (and restored), and
  reads are serialised (Debian's HDF5 is not thread-safe); evaluation never calls HDF5. `npf info`
  shows the layer sizes (not the file's Keras version any more: HDF5 1.10 allocates whatever length a
  variable-length string attribute claims, so no attribute is read; docs/reliability.md).
- **Evaluation.** Input (hx, hy, hz, dx, dy, dz): the half vector h = normalize(wi + wo) entered
  as (sin theta_h, 0, cos theta_h) (isotropic, phi_h = 0), and the difference vector: **wo**
  rotated by -phi_h about the normal and then by -theta_h about the bitangent. Two ReLU layers, a
  linear one, then exp(x) - 1 = f_r in 1/sr for R, G, B; `eval_cos` multiplies by cos theta_o. Float
  throughout, activations on the stack, no allocation. `exp(x) - 1` can be slightly negative
  (cg_sunflower's blue, which is about 0 in the RGL file, is negative in 82 % of random pairs, down
  to -0.0035): clamped to 0 like every RGB source, kept by `npf eval --raw`. The authors' Mitsuba
  plugin clamps too.
- **Sampling.** Cosine-weighted (pdf = cos theta_o / pi), as for MERL: the network has no inverse.
  The authors sample a tabulated microfacet fit instead; that is not reproduced.
- **Options:** none.
)";
    return f;
}

}  // namespace npf
