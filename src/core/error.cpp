#include "bridgefit/core/error.hpp"

namespace bridgefit {

std::string FormatErrorMessage(const std::string& message,
                               const ErrorContext& context) {
  std::string out;
  if (!context.file.empty()) {
    out += context.file;
    if (context.line > 0) out += ":" + std::to_string(context.line);
    out += ": ";
  }
  // Appended piece by piece (GCC 12 warns falsely on chained operator+).
  if (!context.field.empty()) out.append("field '").append(context.field).append("': ");
  out.append(message);
  if (!context.value.empty()) out.append(" (got '").append(context.value).append("')");
  if (!context.expected.empty()) out.append("; expected ").append(context.expected);
  if (!out.empty() && out.back() != '.') out += '.';
  return out;
}

Error::Error(ErrorKind kind, const std::string& message, ErrorContext context)
    : std::runtime_error(FormatErrorMessage(message, context)),
      kind_(kind),
      message_(message),
      context_(std::move(context)) {}

Error Error::WithContext(const ErrorContext& outer) const {
  ErrorContext merged = context_;
  if (merged.file.empty()) merged.file = outer.file;
  if (merged.line == 0) merged.line = outer.line;
  if (merged.field.empty()) merged.field = outer.field;
  if (merged.value.empty()) merged.value = outer.value;
  if (merged.expected.empty()) merged.expected = outer.expected;
  return Error(kind_, message_, merged);
}

}  // namespace bridgefit
