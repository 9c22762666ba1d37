// Splitting delimited text lines (CSV headers, case lists) into fields, one
// implementation for every reader: RFC 4180 quoting ("a,b" is one field, ""
// inside quotes is a quote), fields trimmed of surrounding white space.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace pw::io {

/// `s` without leading and trailing spaces, tabs, CR and LF.
std::string_view trim_space(std::string_view s);

/// Fields of `line` separated by `delimiter`, quotes honoured, each trimmed.
std::vector<std::string> split_fields(std::string_view line, char delimiter = ',');

} // namespace pw::io
