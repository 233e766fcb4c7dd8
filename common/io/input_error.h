// Errors in a user's input (scene files, meshes, command lines): one line that names the file,
// the line and the field, so a typo costs a glance, not a debugging session.
#pragma once

#include <span>
#include <stdexcept>
#include <string>

namespace lessons {

class InputError : public std::runtime_error {
public:
    // Formats as "file:line: field: message" (line omitted when 0, field when empty).
    InputError(const std::string& file, int line, const std::string& field,
               const std::string& message);
    const std::string& file() const { return file_; }
    int line() const { return line_; }
    const std::string& field() const { return field_; }

private:
    std::string file_;
    int line_;
    std::string field_;
};

// The candidate closest to `word` by edit distance, if close enough to be a likely typo;
// else empty.
std::string closest_match(const std::string& word, std::span<const std::string> candidates);
// The suggestion every "unknown name" message ends with: "; did you mean 'x'?" for the closest
// candidate, or nothing.
std::string did_you_mean(const std::string& word, std::span<const std::string> candidates);
// " (known: a, b, c)".
std::string known_names(std::span<const std::string> candidates);

}  // namespace lessons
