// Joining parts (see merge_parts.h).
#include "farm/merge_parts.h"

#include <algorithm>
#include <utility>

#include "io/input_error.h"

namespace lessons {

namespace {

bool overlap(int a0, int a1, int b0, int b1) {
    return a0 < b1 && b0 < a1;
}

std::string pixels_text(int x0, int x1, int y0, int y1) {
    return std::to_string(x0) + ":" + std::to_string(x1) + "," + std::to_string(y0) + ":" +
           std::to_string(y1);
}

std::string lines(const std::vector<std::string>& v) {
    std::string s;
    for (const std::string& l : v) s += (s.empty() ? "" : ", ") + l;
    return s;
}

// The first line where two option lists differ, "--flag=value" or "(none)".
std::pair<std::string, std::string> first_difference(const std::string& a, const std::string& b) {
    auto split = [](const std::string& s) {
        std::vector<std::string> v;
        size_t start = 0;
        for (size_t end; (end = s.find('\n', start)) != std::string::npos; start = end + 1)
            v.push_back(s.substr(start, end - start));
        if (!s.empty()) v.push_back(s.substr(start));
        return v;
    };
    const std::vector<std::string> la = split(a), lb = split(b);
    // The line of `v` for the same flag as `line`, or "(none)".
    const auto same_flag = [](const std::vector<std::string>& v, const std::string& line) {
        const std::string flag = line.substr(0, line.find('=') + 1);
        for (const std::string& l : v)
            if (l.compare(0, flag.size(), flag) == 0) return l;
        return std::string("(none)");
    };
    for (const std::string& l : la)
        if (std::find(lb.begin(), lb.end(), l) == lb.end()) return {l, same_flag(lb, l)};
    for (const std::string& l : lb)
        if (std::find(la.begin(), la.end(), l) == la.end()) return {same_flag(la, l), l};
    return {a, b};
}

}  // namespace

void check_parts_agree(const std::vector<PartFile>& parts) {
    if (parts.empty()) throw InputError("command line", 0, "", "no parts to merge");
    const PartHeader& first = parts[0].header;
    const std::string& first_path = parts[0].path;
    for (const PartFile& p : parts) {
        const PartHeader& h = p.header;
        const auto refuse = [&](const char* field, const std::string& mine,
                                const std::string& theirs) {
            throw InputError(p.path, 0, field,
                             "is '" + mine + "', but " + first_path + " has '" + theirs +
                                 "': parts of different renders do not merge");
        };
        if (h.lesson != first.lesson) refuse("lessons.lesson", h.lesson, first.lesson);
        if (h.scene_hash != first.scene_hash)
            throw InputError(p.path, 0, "lessons.scene_hash",
                             "the scene " + h.scene + " and its files differ from those of " +
                                 first_path + " (" + first.scene +
                                 "): parts of different renders do not merge");
        if (h.options != first.options) {
            const auto [mine, theirs] = first_difference(h.options, first.options);
            refuse("lessons.options", mine, theirs);
        }
        if (h.seed != first.seed)
            refuse("lessons.seed", std::to_string(h.seed), std::to_string(first.seed));
        if (h.image_width != first.image_width || h.image_height != first.image_height)
            refuse("lessons.image",
                   std::to_string(h.image_width) + "x" + std::to_string(h.image_height),
                   std::to_string(first.image_width) + "x" + std::to_string(first.image_height));
        if (h.films != first.films) refuse("lessons.films", lines(h.films), lines(first.films));
    }
}

void check_parts_disjoint(const std::vector<PartFile>& parts) {
    for (size_t i = 0; i < parts.size(); ++i)
        for (size_t j = i + 1; j < parts.size(); ++j) {
            const PartHeader &a = parts[i].header, &b = parts[j].header;
            if (a.sample_end == a.sample_begin || b.sample_end == b.sample_begin) continue;
            if (!overlap(a.x0, a.x1, b.x0, b.x1) || !overlap(a.y0, a.y1, b.y0, b.y1) ||
                !overlap(a.sample_begin, a.sample_end, b.sample_begin, b.sample_end))
                continue;
            const int s0 = std::max(a.sample_begin, b.sample_begin);
            const int s1 = std::min(a.sample_end, b.sample_end);
            throw InputError(
                parts[j].path, 0, "lessons.samples",
                "holds samples " + std::to_string(s0) + ":" + std::to_string(s1) + " of pixels " +
                    pixels_text(std::max(a.x0, b.x0), std::min(a.x1, b.x1), std::max(a.y0, b.y0),
                                std::min(a.y1, b.y1)) +
                    ", which " + parts[i].path + " holds too: merged, they would count them twice");
        }
}

Coverage part_coverage(const std::vector<PartFile>& parts, int target) {
    Coverage c;
    if (parts.empty()) return c;
    const int width = parts[0].header.image_width, height = parts[0].header.image_height;
    if (target <= 0)
        for (const PartFile& p : parts) target = std::max(target, p.header.planned_end);
    c.target = target;
    for (const PartFile& p : parts)
        if (p.header.sample_end > target)
            c.beyond.push_back(p.path + " holds samples " + p.header.samples_text() +
                               ", past the " + std::to_string(target) + " asked for");
    // The image cut along every part's edges: each cell is covered by the same parts throughout.
    std::vector<int> xs{0, width}, ys{0, height};
    for (const PartFile& p : parts) {
        xs.insert(xs.end(), {p.header.x0, p.header.x1});
        ys.insert(ys.end(), {p.header.y0, p.header.y1});
    }
    for (std::vector<int>* v : {&xs, &ys}) {
        std::sort(v->begin(), v->end());
        v->erase(std::unique(v->begin(), v->end()), v->end());
    }
    c.spp_min = target;
    double covered = 0.0;
    for (size_t j = 0; j + 1 < ys.size(); ++j)
        for (size_t i = 0; i + 1 < xs.size(); ++i) {
            const int x0 = xs[i], x1 = xs[i + 1], y0 = ys[j], y1 = ys[j + 1];
            std::vector<std::pair<int, int>> ranges;
            for (const PartFile& p : parts) {
                const PartHeader& h = p.header;
                if (h.x0 <= x0 && x1 <= h.x1 && h.y0 <= y0 && y1 <= h.y1)
                    ranges.emplace_back(h.sample_begin, std::min(h.sample_end, target));
            }
            std::sort(ranges.begin(), ranges.end());
            int held = 0, next = 0;
            const auto gap = [&](int a, int b) {
                c.missing.push_back("samples " + std::to_string(a) + ":" + std::to_string(b) +
                                    " of pixels " + pixels_text(x0, x1, y0, y1));
            };
            for (const auto& [a, b] : ranges) {
                if (b <= a) continue;
                if (a > next) gap(next, a);
                held += b - std::max(a, next) > 0 ? b - std::max(a, next) : 0;
                next = std::max(next, b);
            }
            if (next < target) gap(next, target);
            c.spp_min = std::min(c.spp_min, held);
            c.spp_max = std::max(c.spp_max, held);
            covered += static_cast<double>(held) * (x1 - x0) * (y1 - y0);
        }
    c.fraction = target > 0 ? covered / (static_cast<double>(target) * width * height) : 0.0;
    return c;
}

std::string mixed_builds(const std::vector<PartFile>& parts) {
    for (const PartFile& p : parts) {
        const PartHeader &h = p.header, &first = parts[0].header;
        if (h.build != first.build)
            return p.path + " was made by another build of " + h.lesson + " than " + parts[0].path;
        if (h.cpu != first.cpu)
            return p.path + " was made on another CPU (" + h.cpu + ") than " + parts[0].path +
                   " (" + first.cpu + ")";
    }
    return "";
}

std::vector<Film> merge_parts(const std::vector<PartFile>& parts) {
    const PartHeader& first = parts.at(0).header;
    std::vector<Film> films(first.films.size(), Film(first.image_width, first.image_height));
    for (const PartFile& header : parts) {
        PartFile read;
        const PartFile& p = header.films.empty() ? (read = read_part(header.path)) : header;
        const PartHeader& h = p.header;
        if (!same_header(h, header.header) || p.films.size() != first.films.size())
            throw InputError(p.path, 0, "", "changed while the merge was reading the parts");
        for (size_t f = 0; f < films.size(); ++f) films[f].add_window(p.films[f], h.x0, h.y0);
    }
    return films;
}

}  // namespace lessons
