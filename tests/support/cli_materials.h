// The synthetic RGL files the `npf info` and `npf eval` tests read, written once per test process
// into one folder (removed at exit, kept if NPF_KEEP_TEST_FILES is set).
#pragma once

#include <string>

namespace npf::testing {

// The folder of the CLI tests' files.
const std::string& cli_folder();

struct CliMaterials {
    std::string rgb;        // isotropic RGB, with negative blue values
    std::string spectral;   // anisotropic (reduction 2) spectral, 400..700 nm in 4 steps
    std::string rgb_aniso;  // anisotropic (reduction 1) RGB
};

const CliMaterials& cli_materials();

}  // namespace npf::testing
