// Field-level text helpers shared by the CSV readers: trimming, splitting, number parsing,
// and showing field text in messages (escaped and shortened: the text comes from the file).
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace imuconv::pipeline::data {

/// Without leading spaces/tabs and trailing spaces/tabs/CR.
std::string_view Trim(std::string_view s);
bool IsBlank(std::string_view s);
/// A whole field as a double ("+1" allowed; surrounding blanks ignored; nothing for trailing
/// garbage). Non-finite values ("nan", "inf") are returned: the caller decides.
std::optional<double> ParseDouble(std::string_view s);
/// Splits a line at `delim` (each field trimmed) or at runs of blanks (`whitespace`).
void Split(std::string_view line, char delim, bool whitespace, std::vector<std::string_view>& out);

/// Field text for a message: escaped, at most 40 bytes then "...", in quotes: 'abc'.
std::string Shown(std::string_view s);
/// The same without the quotes (for numbers: "timestamp 2000 is not after ...").
std::string ShownBare(std::string_view s);
/// "',' ", "tab", "whitespace" for messages.
std::string DelimiterName(char d, bool whitespace);

}  // namespace imuconv::pipeline::data
