#pragma once
// The two pieces every JSON writer of ours needs (eval.json, stats.json): a quoted, escaped string and
// a number in shortest round-trip form (JSON has no NaN or infinity: those become null).

#include <string>

namespace asynevo {

std::string jsonQuoted(const std::string& text);
std::string jsonNumber(double value);

}  // namespace asynevo
