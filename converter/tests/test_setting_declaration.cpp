// A newcomer's new conversion setting is one declaration where it is used (issue 36): this file
// declares the detail fit's samples per cell as a setting of its own, and it reaches the help,
// the flags' and batch keys' checks, the resolved settings, the hash text and the metadata with
// no other edit.
#include <npf/batch/config.h>
#include <npf/converter/convert_settings_table.h>
#include <npf/core/error.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <string>

namespace {

using namespace npf;

// The declaration, as a setting's owner writes it.
ConvertSettingRow detail_samples_setting() {
    ConvertSettingRow row;
    row.key = "detail_samples";
    row.kind = SettingKind::Whole;
    row.ranges = {{1, 16}};
    row.help = "samples per detail cell and axis";
    row.apply = [](ConvertSettings& s, const SettingValue& v) { s.detail.samples_per_cell = int(v.numbers[0]); };
    row.read = [](const ConvertSettings& s) { return std::to_string(s.detail.samples_per_cell); };
    row.metadata = [](const ConvertSettings& s) {
        return std::vector<std::pair<std::string, std::string>>{{"detail_samples", std::to_string(s.detail.samples_per_cell)}};
    };
    return row;
}

ConvertSettings resolved(const std::map<std::string, std::string>& values) {
    batch::Settings settings;
    for (const auto& [key, value] : values) settings[key] = {value, "test"};
    return batch::resolve_convert_settings(settings, true);
}

TEST(SettingDeclaration, ANewSettingIsOneDeclaration) {
    const std::string hash_before = convert_settings_hash_text(resolved({{"preset", "fine"}}), true);
    const SettingRegistration registered(SettingGroup::Detail, detail_samples_setting());  // the one line

    // In the table (so in `npf convert --help` and the batch's keys) at the end of its group.
    const ConvertSettingsTable& table = convert_settings_table();
    const ConvertSettingRow* row = find_setting(table, "detail_samples");
    ASSERT_TRUE(row);
    const auto at = std::size_t(row - table.data());
    EXPECT_EQ(table.at(at - 1).key, "detail_views");
    EXPECT_EQ(table.at(at + 1).key, "error_pairs");
    EXPECT_EQ(setting_flag(*row), "--detail-samples");
    EXPECT_EQ(setting_help(*row), "samples per detail cell and axis (default: 3)");

    // Checked alike as a flag and as a batch key.
    EXPECT_EQ(check_setting(*row, "5", "--detail-samples").numbers, std::vector<double>{5});
    EXPECT_THROW(check_setting(*row, "0", "--detail-samples"), Error);
    EXPECT_THROW(check_setting(*row, "x", "detail_samples"), Error);
    const ConvertSettings changed = resolved({{"detail_samples", "5"}, {"preset", "fine"}});
    EXPECT_EQ(changed.detail.samples_per_cell, 5);
    EXPECT_EQ(changed.preset, ConvertPreset::Fine);

    // In the hash text only where it differs from the preset's value, in its sorted place:
    // earlier outputs stay up to date.
    EXPECT_EQ(convert_settings_hash_text(resolved({{"detail_samples", "3"}, {"preset", "fine"}}), true), hash_before);
    std::string expected = hash_before;
    expected.insert(expected.find("epsilon="), "detail_samples=5\n");
    EXPECT_EQ(convert_settings_hash_text(changed, true), expected);
    EXPECT_NE(convert_settings_canonical_text(changed).find("\ndetail_samples=5\n"), std::string::npos);

    // And in the factor texture's metadata, sorted by key.
    const auto lines = convert_settings_metadata(changed);
    const auto line = std::find(lines.begin(), lines.end(), std::pair<std::string, std::string>{"detail_samples", "5"});
    ASSERT_NE(line, lines.end());
    EXPECT_TRUE(std::is_sorted(lines.begin(), lines.end(), [](const auto& a, const auto& b) { return a.first < b.first; }));
}

TEST(SettingDeclaration, ARegistrationEndsWithItsObject) {
    {
        const SettingRegistration registered(SettingGroup::Output, detail_samples_setting());
        EXPECT_TRUE(find_setting(convert_settings_table(), "detail_samples"));
    }
    EXPECT_FALSE(find_setting(convert_settings_table(), "detail_samples"));
}

}  // namespace
