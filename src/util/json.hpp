// JSON text for the reports the CLI prints with --json (ValidationReport::to_json,
// repair_report_json): escaped strings and numbers. Private to the library (not installed).
#pragma once

#include <string>

namespace frep {

// JSON string contents: quotes, backslashes and control characters escaped; well-formed UTF-8
// passes through; any other byte (a file name in Latin-1...) becomes the escape of U+00XX, its
// Latin-1 reading, so the output is always valid JSON.
std::string json_escape(const std::string& s);

// A number with 9 significant digits, or null if it is not finite (JSON has no infinities).
std::string json_num(double v);

}  // namespace frep
