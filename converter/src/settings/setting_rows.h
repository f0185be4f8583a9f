// The conversion settings' rows (private to the converter): the row makers every declaration
// uses, and the groups of rows, each declared in the file of the code that uses them
// (converter/src/settings/*_settings.cpp).
#pragma once

#include <npf/converter/convert_settings_table.h>

#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace npf::settings_rows {

using Row = ConvertSettingRow;
using Rows = std::vector<Row>;
using Lines = std::vector<std::pair<std::string, std::string>>;
using Range = ConvertSettingRow::Range;
constexpr double kAny = std::numeric_limits<double>::infinity();

// Numbers in the canonical text: every digit.
std::string g17(double v);
std::vector<std::string> split(const std::string& v, char separator);
std::string join(const std::vector<std::string>& parts, const char* separator);
std::string range_text(const Range& r);
std::string grid_text(const DetailGrid& g, char separator);

// Row makers: the common kinds in one line each.
Row whole(std::string key, std::vector<Range> ranges, std::string help);
Row number(std::string key, std::size_t least_parts, std::size_t most_parts, std::vector<Range> ranges, std::string range_problem,
           std::string help);
Row choice(std::string key, std::vector<std::string> choices, std::string help);
Row text(std::string key, std::function<void(const std::string&, const std::string&)> check, std::string help);
Row switched(std::string key, std::string help);
// In the hash text whatever its value.
Row always_hashed(Row r);
// Set by the presets alone (ConvertSettingRow::preset_only).
Row preset_only(Row r);

// The groups (SettingGroup), each from the file of the code that uses it.
Rows source_settings();      // source_settings.cpp: what is fitted
Rows fit_grid_settings();    // fit_settings.cpp: the fit's grids and the SVD's compression
Rows fit_weight_settings();  // fit_settings.cpp: the fit's weights and iterations
Rows detail_settings();      // detail_settings.cpp: the detail layer
Rows output_settings();      // output_settings.cpp: the measurements, the prediction, threads

// Every row, the presets' own included, in help order (convert_settings_table.cpp).
const ConvertSettingsTable& all_settings();

}  // namespace npf::settings_rows
