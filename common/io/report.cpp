// The JSON report of a render, written atomically.
#include "io/report.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <stdexcept>

#include "io/image.h"

namespace lessons {

std::string json_quote(const std::string& s) {
    std::string out = "\"";
    for (const char c : s) {
        switch (c) {
            case '"': out += "\\\""; break;
            case '\\': out += "\\\\"; break;
            case '\n': out += "\\n"; break;
            case '\t': out += "\\t"; break;
            default:
                if (static_cast<unsigned char>(c) < 0x20) {
                    char buf[8];
                    std::snprintf(buf, sizeof buf, "\\u%04x", c);
                    out += buf;
                } else {
                    out += c;
                }
        }
    }
    return out + "\"";
}

void Report::put(const std::string& key, std::string json_value) {
    for (auto& [k, v] : fields_)
        if (k == key) {
            v = std::move(json_value);
            return;
        }
    fields_.emplace_back(key, std::move(json_value));
}

void Report::set(const std::string& key, const std::string& value) {
    put(key, json_quote(value));
}
void Report::set(const std::string& key, double value) {
    if (!std::isfinite(value)) {
        put(key, "null");  // JSON has no NaN or infinity
        return;
    }
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.9g", value);
    put(key, buf);
}
void Report::set(const std::string& key, int64_t value) {
    put(key, std::to_string(value));
}
void Report::set(const std::string& key, uint64_t value) {
    put(key, std::to_string(value));
}
void Report::set(const std::string& key, bool value) {
    put(key, value ? "true" : "false");
}
void Report::set(const std::string& key, const std::vector<std::string>& values) {
    std::string json = "[";
    for (size_t i = 0; i < values.size(); ++i) {
        if (i > 0) json.append(", ");
        json.append(json_quote(values[i]));
    }
    json.append("]");
    put(key, json);
}

std::string Report::to_json() const {
    std::string json = "{\n";
    for (size_t i = 0; i < fields_.size(); ++i)
        json += "  " + json_quote(fields_[i].first) + ": " + fields_[i].second +
                (i + 1 < fields_.size() ? ",\n" : "\n");
    return json + "}\n";
}

void Report::write(const std::string& path) const {
    write_atomically(path, [&](const std::string& tmp) {
        std::ofstream out(tmp);
        out << to_json();
        out.close();
        if (!out) {
            std::remove(tmp.c_str());
            throw std::runtime_error(path + ": cannot write report");
        }
    });
}

}  // namespace lessons
