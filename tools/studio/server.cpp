// studio: the lessons, live, in a browser (docs/studio.md). An HTTP server (cpp-httplib) on
// 127.0.0.1 that serves one page (tools/studio/page, shipped as share/illumination-lessons/page)
// and the API it polls:
//
//   GET  /api/config                  scenes, lessons and their flags, limits, the bind address
//   POST /api/start?pane=P&scene=S&lesson=L&--flag=V...   (re)starts pane P; 400 on bad input
//   POST /api/stop?pane=P
//   GET  /api/status                  every pane: spp, passes, times, rays/s, notes, error chart
//   GET  /api/frame?pane=P&view=V&exposure=X     PNG (view: image, layer:K, sum:K, error)
//   GET  /api/probe?pane=P&x=X&y=Y&light=K       JSON: what is at a pixel, with units
//   GET  /api/download?pane=P&format=exr|png     the image as the CLI writes it
//
// A bad request is a 400 with {"error": message} (a failure of the studio itself, a 500). POSTs
// must carry the header "X-Studio: 1", which the page sends and which a page of another site
// cannot send without the browser asking first (and this server never says yes): another site
// open in the teacher's browser cannot start renders. The render core is studio.h.
#include <httplib.h>
#include <malloc.h>
#include <signal.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>
#include <thread>

#include "io/report.h"
#include "io/shipped_files.h"
#include "studio.h"

using namespace lessons;
using namespace lessons::studio;

namespace {

std::string error_json(const std::string& message) {
    return "{\"error\": " + json_quote(message) + "}";
}

// POSTs come from the studio's own page (see the top of this file).
void require_page_header(const httplib::Request& req) {
    if (req.get_header_value("X-Studio") != "1")
        throw RequestError("this request must come from the studio's page (header X-Studio: 1)");
}

// The query's parameters, each once.
Params params_of(const httplib::Request& req) {
    Params params;
    for (const auto& [key, value] : req.params)
        if (!params.emplace(key, value).second)
            throw RequestError("parameter '" + key + "' given twice");
    return params;
}

int int_of(const Params& params, const std::string& key, int fallback) {
    const auto it = params.find(key);
    if (it == params.end()) return fallback;
    try {
        size_t used = 0;
        const int v = std::stoi(it->second, &used);
        if (used == it->second.size()) return v;
    } catch (const std::exception&) {
    }
    throw RequestError(key + ": '" + it->second + "' is not an integer");
}

float exposure_of(const Params& params) {
    const auto it = params.find("exposure");
    if (it == params.end() || it->second.empty()) return 0.0f;
    try {
        size_t used = 0;
        const float v = std::stof(it->second, &used);
        if (used == it->second.size() && v >= -30.0f && v <= 30.0f) return v;
    } catch (const std::exception&) {
    }
    throw RequestError("exposure: '" + it->second + "' is not a number of stops in -30 .. 30");
}

std::string config_json(const Studio& studio, const std::string& bind, int port) {
    std::string s = "{\"bind\": " + json_quote(bind) + ", \"port\": " + std::to_string(port);
    s += ", \"loopback_only\": " + std::string(bind == "127.0.0.1" ? "true" : "false");
    s += ", \"panes\": " + std::to_string(studio.pane_count());
    s += ", \"max_size\": " + std::to_string(studio.limits().max_side);
    s += ", \"max_spp\": " + std::to_string(studio.limits().max_spp);
    s += ", \"reference_spp\": " + std::to_string(studio.limits().reference_spp);
    s += ", \"scenes\": [";
    for (size_t i = 0; i < studio.scenes().size(); ++i) {
        const SceneEntry& e = studio.scenes()[i];
        s += std::string(i ? ", " : "") + "{\"id\": " + json_quote(e.id) +
             ", \"description\": " + json_quote(e.description);
        if (e.reference_width > 0)
            s += ", \"reference_size\": [" + std::to_string(e.reference_width) + ", " +
                 std::to_string(e.reference_height) + "]";
        s += "}";
    }
    s += "], \"lessons\": [";
    for (size_t i = 0; i < studio.lessons().size(); ++i) {
        const LessonInfo& l = studio.lessons()[i];
        s += std::string(i ? ", " : "") + "{\"name\": " + json_quote(l.name) +
             ", \"label\": " + json_quote(l.label) +
             ", \"description\": " + json_quote(l.description) +
             ", \"default_spp\": " + std::to_string(l.default_spp) + ", \"options\": [";
        for (size_t k = 0; k < l.options.size(); ++k) {
            const OptionInfo& o = l.options[k];
            s += std::string(k ? ", " : "") + "{\"flag\": " + json_quote(o.flag) +
                 ", \"description\": " + json_quote(o.description) +
                 ", \"is_flag\": " + (o.is_flag ? "true" : "false") +
                 ", \"default\": " + json_quote(o.default_value) + ", \"choices\": [";
            for (size_t c = 0; c < o.choices.size(); ++c)
                s += std::string(c ? ", " : "") + json_quote(o.choices[c]);
            s += "]}";
        }
        s += "]}";
    }
    return s + "]}";
}

// Runs `handler`, answering a RequestError with 400 and anything else with 500.
template <class Handler>
httplib::Server::Handler guarded(Handler handler) {
    return [handler](const httplib::Request& req, httplib::Response& res) {
        try {
            handler(req, res);
        } catch (const RequestError& e) {
            res.status = 400;
            res.set_content(error_json(e.what()), "application/json");
        } catch (const std::exception& e) {
            res.status = 500;
            res.set_content(error_json(e.what()), "application/json");
        }
    };
}

// The API (see the top of this file), each handler guarded: RequestError -> 400.
void add_routes(httplib::Server& server, Studio& studio, const std::string& bind, const int& port) {
    server.Get("/api/config",
               guarded([&studio, &bind, &port](const httplib::Request&, httplib::Response& res) {
                   res.set_content(config_json(studio, bind, port), "application/json");
               }));
    server.Post("/api/start",
                guarded([&studio](const httplib::Request& req, httplib::Response& res) {
                    require_page_header(req);
                    Params params = params_of(req);
                    const int pane = int_of(params, "pane", 0);
                    const uint64_t generation = studio.start(pane, params);
                    res.set_content("{\"generation\": " + std::to_string(generation) + "}",
                                    "application/json");
                }));
    server.Post("/api/stop",
                guarded([&studio](const httplib::Request& req, httplib::Response& res) {
                    require_page_header(req);
                    studio.stop_pane(int_of(params_of(req), "pane", 0));
                    res.set_content("{}", "application/json");
                }));
    server.Get("/api/status", guarded([&studio](const httplib::Request&, httplib::Response& res) {
                   res.set_content(studio.status_json(), "application/json");
               }));
    server.Get("/api/frame",
               guarded([&studio](const httplib::Request& req, httplib::Response& res) {
                   const Params params = params_of(req);
                   const auto view = params.find("view");
                   res.set_content(studio.frame_png(int_of(params, "pane", 0),
                                                    view == params.end() ? "image" : view->second,
                                                    exposure_of(params)),
                                   "image/png");
               }));
    server.Get(
        "/api/probe", guarded([&studio](const httplib::Request& req, httplib::Response& res) {
            const Params params = params_of(req);
            res.set_content(studio.probe_json(int_of(params, "pane", 0), int_of(params, "x", -1),
                                              int_of(params, "y", -1), int_of(params, "light", 0),
                                              int_of(params, "samples", 1024)),
                            "application/json");
        }));
    server.Get(
        "/api/download", guarded([&studio](const httplib::Request& req, httplib::Response& res) {
            const Params params = params_of(req);
            const auto format = params.find("format");
            const std::string f = format == params.end() ? "exr" : format->second;
            int spp = 0;
            const int pane = int_of(params, "pane", 0);
            const std::string bytes = studio.download(pane, f, exposure_of(params), &spp);
            res.set_header("X-Studio-Spp", std::to_string(spp));
            res.set_header("Content-Disposition", "attachment; filename=\"studio_pane" +
                                                      std::to_string(pane) + "_" +
                                                      std::to_string(spp) + "spp." + f + "\"");
            res.set_content(bytes, f == "exr" ? "image/x-exr" : "image/png");
        }));
}

// The studio's flags.
struct ServerOptions {
    int port = 8642;
    std::string bind = "127.0.0.1";
    std::vector<std::pair<std::string, std::string>> folders;  // (label, folder) of scenes
    // The shipped references first (common/io/shipped_files.h: installed or in the build tree),
    // then those scripts/lessons.sh renders for other settings, relative to the folder the
    // studio starts in, as a lesson's out/ is (scripts/studio.sh starts it in the repository).
    std::vector<std::string> references = {(shipped_files_dir() / "references").string(), "out"};
    std::string cache = "out/studio";
    // Shipped beside the program (common/io/shipped_files.h): installed or in the build tree.
    std::string page = (shipped_files_dir() / "page").string();
    Limits limits;
};

// Reads the command line into `o`; an exit status if the studio stops here (--help: 0, bad: 2).
// The studio's flags, each bound to its place in `o` (the scene folders to `scene_dirs`).
void declare_options(CLI::App& app, ServerOptions& o, std::vector<std::string>& scene_dirs) {
    app.add_option("--port", o.port, "TCP port (0: any free port; the address is printed)")
        ->check(CLI::Range(0, 65535))
        ->capture_default_str();
    app.add_option("--bind", o.bind,
                   "Address to listen on. Only 127.0.0.1 (this machine) unless you give another "
                   "one, e.g. 0.0.0.0 to let a classroom's machines in; the page then says so")
        ->capture_default_str();
    app.add_option("--scenes", scene_dirs,
                   "Folders of scene files the page may choose from, each given once (default: "
                   "the scenes/ and scenes/hard/ the suite ships); no other file can be chosen");
    app.add_option("--references", o.references,
                   "Folders of references, <dir>/<scene>/reference.exr, looked for in order "
                   "(repeat the flag): the shipped ones and those scripts/lessons.sh rendered")
        ->capture_default_str();
    app.add_option("--cache", o.cache, "Where the studio keeps the references it renders")
        ->capture_default_str();
    app.add_option("--page", o.page, "The folder of the page's files")->capture_default_str();
    app.add_option("--max-size", o.limits.max_side, "Largest image side a page may ask for")
        ->check(CLI::Range(16, 8192))
        ->capture_default_str();
    app.add_option("--max-spp", o.limits.max_spp, "A pane's render stops at this many samples")
        ->check(CLI::Range(1, 1 << 24))
        ->capture_default_str();
    app.add_option("--threads", o.limits.threads, "Threads per pass (0: one per core)")
        ->check(CLI::Range(0, 1024))
        ->capture_default_str();
    app.add_option("--max-memory-mb", o.limits.memory_mb,
                   "Largest memory one render's films may take (larger requests are refused)")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    app.add_option("--reference-spp", o.limits.reference_spp,
                   "Samples per pixel of a reference the studio renders itself")
        ->check(CLI::Range(1, 1 << 20))
        ->capture_default_str();
}

// The scene folders the page may choose from, each labelled by its own name; false (said on
// stderr) for one that is not a folder.
bool read_scene_folders(std::vector<std::string> scene_dirs, ServerOptions& o) {
    if (scene_dirs.empty())
        scene_dirs = {(shipped_files_dir() / "scenes").string(),
                      (shipped_files_dir() / "scenes" / "hard").string()};
    for (const std::string& dir : scene_dirs) {
        std::error_code ec;
        if (!std::filesystem::is_directory(dir, ec)) {
            std::cerr << "studio: error: command line: --scenes: '" << dir << "' is not a folder\n";
            return false;
        }
        // The folder's own name labels its scenes ("scenes/cornell_box", "hard/cornell_tiny").
        std::filesystem::path name = std::filesystem::path(dir).lexically_normal();
        if (name.filename().empty()) name = name.parent_path();
        o.folders.emplace_back(name.filename().string(), dir);
    }
    return true;
}

std::optional<int> read_options(int argc, char** argv, ServerOptions& o) {
    CLI::App app(
        "studio: the lessons rendering live in a browser, two side by side, with the error "
        "against a reference as they converge (docs/studio.md)",
        "studio");
    std::vector<std::string> scene_dirs;
    declare_options(app, o, scene_dirs);
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        std::cerr << "studio: error: command line: " << e.what() << " (see --help)\n";
        return 2;
    }
    if (!read_scene_folders(scene_dirs, o)) return 2;
    if (!std::filesystem::is_regular_file(o.page + "/index.html")) {
        std::cerr << "studio: error: command line: --page: no index.html in '" << o.page << "'\n";
        return 2;
    }
    return std::nullopt;
}

}  // namespace

int main(int argc, char** argv) {
    ServerOptions o;
    if (const std::optional<int> status = read_options(argc, argv, o)) return *status;
    std::string& bind = o.bind;
    int& port = o.port;

    // The HTTP server's pool has a dozen threads; glibc would give each one its own malloc arena,
    // each holding on to memory it freed, and the studio's memory would grow with the number of
    // threads that ever served a request (measured: +9 MB over the first 40 page reloads, flat
    // with two arenas). Two arenas: one per core.
    mallopt(M_ARENA_MAX, 2);

    // Ctrl-C and SIGTERM go to one thread, which stops the server; every other thread (created
    // after this) has them blocked.
    sigset_t stop_signals;
    sigemptyset(&stop_signals);
    sigaddset(&stop_signals, SIGINT);
    sigaddset(&stop_signals, SIGTERM);
    pthread_sigmask(SIG_BLOCK, &stop_signals, nullptr);

    Studio studio(o.folders, o.references, o.cache, o.limits);
    httplib::Server server;
    server.set_payload_max_length(1 << 16);
    server.set_keep_alive_max_count(100);
    server.set_mount_point("/", o.page);
    server.set_file_extension_and_mimetype_mapping("js", "text/javascript");
    server.set_default_headers({{"Cache-Control", "no-store"}});

    add_routes(server, studio, bind, port);

    if (port == 0) {
        port = server.bind_to_any_port(bind);
    } else if (!server.bind_to_port(bind, port)) {
        port = -1;
    }
    if (port < 0) {
        std::cerr << "studio: error: cannot listen on " << bind << " (port in use, or not an "
                  << "address of this machine)\n";
        return 2;
    }
    std::thread signals([&] {
        int signal_number = 0;
        sigwait(&stop_signals, &signal_number);
        std::fprintf(stderr, "\nstudio: stopping\n");
        server.stop();
    });
    std::printf(
        "studio: serving http://%s:%d/%s\n", bind.c_str(), port,
        bind == "127.0.0.1" ? "" : "  (not only this machine: every host that can reach it)");
    std::fflush(stdout);
    server.listen_after_bind();
    studio.shutdown();
    // The signal thread ends with the signal that stopped the server, or is woken to end here.
    pthread_kill(signals.native_handle(), SIGTERM);
    signals.join();
    return 0;
}
