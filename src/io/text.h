// Small text helpers shared by the file readers of io/ (ASCII only; "white space" is
// std::isspace in the C locale).
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace stickslip::text {

std::string trim(std::string_view s);   // leading and trailing white space removed
std::string rtrim(std::string_view s);  // trailing white space removed
std::string upper(std::string s);
std::string lower(std::string s);
// The white-space separated words of s (none for a blank line).
std::vector<std::string> split_whitespace(std::string_view s);
// The comma-separated fields of s, each trimmed ("a, ,b" -> "a", "", "b"; "" -> one empty field).
std::vector<std::string> split_commas(std::string_view s);

}  // namespace stickslip::text
