// relief serve [--port N] [--root DIR]: the material preview web page (web/) and the engine
// shader library (shaders/relief/) over HTTP on 127.0.0.1 only, through cpp-httplib. URLs: / and
// /FILE from DIR/web, /shaders/relief/FILE from DIR/shaders/relief, /gl/preview_*.glsl from
// DIR/src/relief/gl/shaders; nothing else is served (no listing, no path outside those folders,
// symbolic links resolved before the check); --data DIR adds /data/FILE from DIR.
#include <httplib.h>
#include <relief/cli/common.h>
#include <sys/socket.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

namespace relief::cli {

namespace {

namespace fs = std::filesystem;

struct ServeOptions {
    int port = 8642;
    std::string root = RELIEF_SOURCE_DIR;
    std::string data;  // optional: served under /data/ (heightmaps and maps for ?height=&map=)
};

const char* contentType(const fs::path& path) {
    const std::string ext = path.extension().string();
    if (ext == ".html") return "text/html; charset=utf-8";
    if (ext == ".js" || ext == ".mjs") return "text/javascript; charset=utf-8";
    if (ext == ".css") return "text/css; charset=utf-8";
    if (ext == ".png") return "image/png";
    if (ext == ".json") return "application/json";
    if (ext == ".ktx2") return "image/ktx2";
    return "text/plain; charset=utf-8";  // .glsl, .md
}

// `relative` (the URL path below a mount point) inside `base`, or nothing: ".." parts, absolute
// parts and links that lead out of `base` are refused.
std::optional<fs::path> insideRoot(const fs::path& base, const std::string& relative) {
    std::error_code ec;
    const fs::path root = fs::weakly_canonical(base, ec);
    if (ec) return std::nullopt;
    const fs::path candidate = fs::weakly_canonical(root / fs::path(relative).relative_path(), ec);
    if (ec) return std::nullopt;
    auto [end, unused] =
        std::mismatch(root.begin(), root.end(), candidate.begin(), candidate.end());
    if (end != root.end()) return std::nullopt;
    if (!fs::is_regular_file(candidate, ec)) return std::nullopt;
    return candidate;
}

void runServe(const ServeOptions& o) {
    const fs::path root(o.root);
    const fs::path web = root / "web", library = root / "shaders" / "relief",
                   glShaders = root / "src" / "relief" / "gl" / "shaders";
    for (const fs::path& dir : {web, library, glShaders})
        if (!fs::is_directory(dir))
            throw CommandFailed{makeError(ErrorKind::Io,
                                          "--root {}: no folder {} (the repository root holds "
                                          "web/ and shaders/relief/)",
                                          o.root, dir.string())};
    httplib::Server server;
    auto send = [](httplib::Response& res, const std::optional<fs::path>& file) {
        if (!file) {
            res.status = 404;
            res.set_content("not found\n", "text/plain");
            return;
        }
        std::ifstream in(*file, std::ios::binary);
        std::ostringstream bytes;
        bytes << in.rdbuf();
        res.set_header("Cache-Control", "no-cache");
        res.set_content(bytes.str(), contentType(*file));
    };
    server.Get("/shaders/relief/(.*)", [&](const httplib::Request& req, httplib::Response& res) {
        send(res, insideRoot(library, req.matches[1]));
    });
    // The mesh preview's own shaders, which the page shares with `relief render --mesh`.
    server.Get("/gl/(preview_[a-z]+\\.glsl)",
               [&](const httplib::Request& req, httplib::Response& res) {
                   send(res, insideRoot(glShaders, req.matches[1]));
               });
    if (!o.data.empty()) {
        if (!fs::is_directory(o.data))
            throw CommandFailed{makeError(ErrorKind::Io, "--data {}: not a folder", o.data)};
        server.Get("/data/(.*)", [&](const httplib::Request& req, httplib::Response& res) {
            send(res, insideRoot(o.data, req.matches[1]));
        });
    }
    server.Get("/(.*)", [&](const httplib::Request& req, httplib::Response& res) {
        const std::string path = req.matches[1];
        send(res, insideRoot(web, path.empty() ? "index.html" : path));
    });
    // Not httplib's default SO_REUSEPORT, under which a second server would share a port in use.
    server.set_socket_options([](auto socket) {
        const int yes = 1;
        ::setsockopt(socket, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
    });
    // Bind first, so that a port in use is an error before anything is printed as served.
    if (!server.bind_to_port("127.0.0.1", o.port))
        throw CommandFailed{makeError(ErrorKind::Io,
                                      "--port {}: cannot listen on 127.0.0.1:{} (in use by another "
                                      "program? try another --port)",
                                      o.port, o.port)};
    std::cout << fmt::format(
                     "relief serve: http://127.0.0.1:{}/ (web/ and shaders/relief/ from "
                     "{}); Ctrl-C stops\n",
                     o.port, fs::weakly_canonical(root).string())
              << std::flush;
    if (!server.listen_after_bind())
        throw CommandFailed{makeError(ErrorKind::Runtime, "relief serve: the server stopped")};
}

}  // namespace

void addServeCommand(CLI::App& app) {
    auto o = std::make_shared<ServeOptions>();
    CLI::App* cmd = app.add_subcommand(
        "serve", "serve the material preview web page (web/) and the shader library on localhost");
    cmd->add_option("--port", o->port, "TCP port on 127.0.0.1")
        ->check(CLI::Range(1, 65535))
        ->capture_default_str();
    cmd->add_option("--root", o->root, "folder holding web/ and shaders/relief/")
        ->capture_default_str();
    cmd->add_option("--data", o->data,
                    "also serve this folder's files under /data/ (links such as "
                    "/?height=/data/h.png&map=/data/h.cone.png)");
    cmd->callback([o] { runServe(*o); });
}

}  // namespace relief::cli
