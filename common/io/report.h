// The --report JSON file: what was rendered, how long it took, what it cost, what went wrong.
#pragma once

#include <cstdint>
#include <string>
#include <variant>
#include <vector>

namespace lessons {

// A flat JSON object, fields in insertion order.
class Report {
public:
    void set(const std::string& key, const std::string& value);
    void set(const std::string& key, const char* value) { set(key, std::string(value)); }
    void set(const std::string& key, double value);
    void set(const std::string& key, int64_t value);
    void set(const std::string& key, int value) { set(key, static_cast<int64_t>(value)); }
    void set(const std::string& key, uint64_t value);
    void set(const std::string& key, bool value);
    void set(const std::string& key, const std::vector<std::string>& values);

    std::string to_json() const;
    void write(const std::string& path) const;  // atomically

private:
    void put(const std::string& key, std::string json_value);
    std::vector<std::pair<std::string, std::string>> fields_;
};

std::string json_quote(const std::string& s);

}  // namespace lessons
