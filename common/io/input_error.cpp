// One-line input errors, and the edit distance behind "did you mean".
#include "io/input_error.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <vector>

namespace lessons {

namespace {

// The length of the valid UTF-8 sequence starting at s[i], or 0.
size_t utf8_length(const std::string& s, size_t i) {
    const unsigned char c = static_cast<unsigned char>(s[i]);
    const size_t n = c >= 0xF0 && c <= 0xF4 ? 4 : c >= 0xE0 ? 3 : c >= 0xC2 && c <= 0xDF ? 2 : 0;
    if (n == 0 || c >= 0xF5 || i + n > s.size()) return 0;
    for (size_t k = 1; k < n; ++k)
        if ((static_cast<unsigned char>(s[i + k]) & 0xC0) != 0x80) return 0;
    return n;
}

// Control bytes and broken UTF-8 as \xNN: a message from a binary file must not write raw bytes
// to the terminal. Long messages are cut.
std::string printable(const std::string& s) {
    std::string out;
    for (size_t i = 0; i < s.size() && out.size() < 600; ++i) {
        const unsigned char c = static_cast<unsigned char>(s[i]);
        if (c >= 0x20 && c < 0x7F) {
            out += static_cast<char>(c);
        } else if (const size_t n = c >= 0x80 ? utf8_length(s, i) : 0) {
            out.append(s, i, n);
            i += n - 1;
        } else {
            char hex[8];
            std::snprintf(hex, sizeof hex, "\\x%02X", c);
            out += hex;
        }
    }
    if (out.size() >= 600) out += "...";
    return out;
}

std::string format(const std::string& file, int line, const std::string& field,
                   const std::string& message) {
    std::string s = printable(file);
    if (line > 0) s.append(":").append(std::to_string(line));
    s.append(": ");
    if (!field.empty()) s.append(printable(field)).append(": ");
    return s.append(printable(message));
}

// Levenshtein distance, case-insensitive.
size_t edit_distance(const std::string& a, const std::string& b) {
    std::vector<size_t> row(b.size() + 1);
    for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
    for (size_t i = 1; i <= a.size(); ++i) {
        size_t diagonal = row[0];
        row[0] = i;
        for (size_t j = 1; j <= b.size(); ++j) {
            const size_t above = row[j];
            const bool same = std::tolower(static_cast<unsigned char>(a[i - 1])) ==
                              std::tolower(static_cast<unsigned char>(b[j - 1]));
            row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (same ? 0 : 1)});
            diagonal = above;
        }
    }
    return row[b.size()];
}
}  // namespace

InputError::InputError(const std::string& file, int line, const std::string& field,
                       const std::string& message)
    : std::runtime_error(format(file, line, field, message)),
      file_(file),
      line_(line),
      field_(field) {}

std::string did_you_mean(const std::string& word, std::span<const std::string> candidates) {
    const std::string guess = closest_match(word, candidates);
    return guess.empty() ? "" : "; did you mean '" + guess + "'?";
}

std::string known_names(std::span<const std::string> candidates) {
    std::string list;
    for (const std::string& c : candidates) list += (list.empty() ? "" : ", ") + c;
    return " (known: " + list + ")";
}

std::string closest_match(const std::string& word, std::span<const std::string> candidates) {
    std::string best;
    size_t best_distance = std::max<size_t>(2, word.size() / 3) + 1;
    for (const std::string& c : candidates) {
        const size_t d = edit_distance(word, c);
        if (d < best_distance) {
            best_distance = d;
            best = c;
        }
    }
    return best;
}

}  // namespace lessons
