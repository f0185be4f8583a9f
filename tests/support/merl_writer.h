// Writes MERL `.binary` files for tests (the reader's format, converter/merl_brdf.h): no real
// MERL file needs to be present. npf reads MERL files and never writes them, so the writer is
// test support, not product.
#pragma once

#include <functional>
#include <string>

namespace npf::testing {

// A MERL file of the given dimensions at `path`: the three int32 dimensions, then the table of
// doubles (R, G, B planes; phi_d fastest, then theta_d, then theta_h). `fill` is called once per
// bin and sets the three STORED numbers (f_r / channel scale, negative for invalid bins). Writes
// any dimensions, hostile ones included; fails the test when the file cannot be written.
void write_merl(const std::string& path, int n_th, int n_td, int n_pd,
                const std::function<void(int ith, int itd, int ipd, double rgb_stored[3])>& fill);

}  // namespace npf::testing
