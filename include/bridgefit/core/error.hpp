#pragma once
// The one exception type of bridgefit, with context, and the check macros.

#include <stdexcept>
#include <string>

namespace bridgefit {

// What kind of failure: decides the CLI exit code (usage -> 2, interrupted ->
// 128 + signal, others -> 1).
enum class ErrorKind {
  kInput,    // bad data or file: missing column, wrong unit, corrupt image
  kUsage,    // bad command-line use: conflicting or missing options
  kRuntime,  // a computation failed (solver diverged, I/O failed)
  kInternal,    // a broken invariant: a bug
  kInterrupted  // SIGINT / SIGTERM (core/interrupt.hpp): exit 128 + signal
};

// Where an error was found; every field is optional.
struct ErrorContext {
  std::string file;      // file the value came from
  int line = 0;          // 1-based line in that file, 0 when unknown
  std::string field;     // key, column or option name
  std::string value;     // the offending value as read
  std::string expected;  // what would have been accepted
};

// bridgefit::Error: what() is one sentence naming file, line, field, value
// and what was expected, built from the context.
class Error : public std::runtime_error {
 public:
  Error(ErrorKind kind, const std::string& message, ErrorContext context = {});
  Error(const std::string& message, ErrorContext context = {})
      : Error(ErrorKind::kInput, message, std::move(context)) {}

  ErrorKind kind() const { return kind_; }
  const ErrorContext& context() const { return context_; }
  const std::string& message() const { return message_; }

  // Returns a copy with missing context fields filled from `outer`
  // (e.g. a units error rethrown with the file and key it came from).
  Error WithContext(const ErrorContext& outer) const;

 private:
  ErrorKind kind_;
  std::string message_;
  ErrorContext context_;
};

std::string FormatErrorMessage(const std::string& message,
                               const ErrorContext& context);

}  // namespace bridgefit

// Always-on check for inputs: throws bridgefit::Error(kInput).
#define BF_CHECK_INPUT(condition, message, ...)                    \
  do {                                                             \
    if (!(condition))                                              \
      throw ::bridgefit::Error(::bridgefit::ErrorKind::kInput,     \
                               (message), ##__VA_ARGS__);          \
  } while (0)

// Debug-only assert for internal invariants.
#ifdef NDEBUG
#define BF_DEBUG_ASSERT(condition) ((void)0)
#else
#define BF_DEBUG_ASSERT(condition)                                          \
  do {                                                                      \
    if (!(condition))                                                       \
      throw ::bridgefit::Error(::bridgefit::ErrorKind::kInternal,           \
                               std::string("invariant failed: ") +          \
                                   #condition + " at " + __FILE__ + ":" +   \
                                   std::to_string(__LINE__));               \
  } while (0)
#endif
