// The conversion settings' rows (private to the converter): the row makers and the groups of
// rows convert_settings_table.cpp puts together.
#pragma once

#include <npf/converter/convert_settings_table.h>

#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace npf::settings_rows {

using Row = ConvertSettingRow;
using Lines = std::vector<std::pair<std::string, std::string>>;
using Range = ConvertSettingRow::Range;
constexpr double kAny = std::numeric_limits<double>::infinity();

// Numbers in hash text: every digit (content hash version 1).
std::string g17(double v);
std::vector<std::string> split(const std::string& v, char separator);
std::string join(const std::vector<std::string>& parts, const char* separator);
std::string range_text(const Range& r);

// The groups, in the order of `npf convert --help`.
void add_source_rows(ConvertSettingsTable& t);
void add_grid_rows(ConvertSettingsTable& t);
void add_weight_rows(ConvertSettingsTable& t);
void add_detail_rows(ConvertSettingsTable& t);
void add_output_rows(ConvertSettingsTable& t);

}  // namespace npf::settings_rows
