#include "frontends/serve/view_server.h"

#include "sim/core/input_error.h"
#include "sim/core/json_input.h"

#include <fmt/core.h>
#include <httplib.h>

#include <cstdlib>
#include <exception>
#include <mutex>
#include <regex>

namespace pp5 {

namespace {

// Connections served at once. Each holds a worker while it sends its request, so a few clients that
// trickle bytes must not take them all: a valid request still finds a free worker at once.
constexpr std::size_t kWorkers = 64;
// More header lines than any browser sends: a request with more is refused, not served.
constexpr std::size_t kMostHeaders = 100;

void send_json(httplib::Response& response, int status, const nlohmann::json& body) {
    response.status = status;
    // A reason may quote the request, whose bytes need not be UTF-8: those are replaced, not a 500.
    response.set_content(body.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace), "application/json");
}

void send_error(httplib::Response& response, int status, const std::string& field, const std::string& reason) {
    send_json(response, status,
              {{"error", field.empty() ? reason : field + ": " + reason}, {"field", field}, {"reason", reason}});
}

void no_caching(httplib::Response& response) { response.set_header("Cache-Control", "no-store"); }

// The methods each path answers (HEAD as GET); another method on one of them is a 405.
const char* methods_of(const std::string& path) {
    static const std::regex pass_picture(R"(/api/pass/\d{1,3}\.png)");
    if (path == "/" || path == "/api/state" || path == "/api/image.png" || path == "/api/timeline.json" ||
        path == "/api/tiles.png" || path == "/api/fidelity.json" || std::regex_match(path, pass_picture))
        return "GET, HEAD";
    static const std::regex compared_picture(R"(/api/compare/[a-z0-9_-]{1,64}\.png)");
    if (std::regex_match(path, compared_picture)) return "GET, HEAD";
    if (path == "/api/change" || path == "/api/compare") return "POST";
    return nullptr;
}

// What is checked before a request's body is read or it is routed.
httplib::Server::HandlerResponse screen(const httplib::Request& req, httplib::Response& res) {
    if (req.headers.size() > kMostHeaders) {
        send_error(res, 431, "headers",
                   fmt::format("{} header lines; at most {} are read", req.headers.size(), kMostHeaders));
        return httplib::Server::HandlerResponse::Handled;
    }
    // Only a change has a body; /api/change reads a chunked one itself, up to the size limit.
    if (req.has_header("Transfer-Encoding") && req.path != "/api/change") {
        send_error(res, 411, "Transfer-Encoding", "only a change to /api/change has a body");
        return httplib::Server::HandlerResponse::Handled;
    }
    if (const char* allowed = methods_of(req.path)) {
        const std::string list = allowed;
        const bool get_like = req.method == "GET" || req.method == "HEAD";
        if (!(get_like && list.starts_with("GET")) && list != req.method) {
            res.set_header("Allow", list);
            send_error(res, 405, "method", fmt::format("{} is not served at {} ({} is)", req.method, req.path, list));
            return httplib::Server::HandlerResponse::Handled;
        }
    }
    return httplib::Server::HandlerResponse::Unhandled;
}

}  // namespace

struct ViewServer::Impl {
    InteractiveView& view;
    ServeOptions options;
    httplib::Server server;
    std::mutex mutex;  // one request at a time touches the view
    int port = -1;

    Impl(InteractiveView& v, ServeOptions o) : view(v), options(std::move(o)) {
        set_limits();
        route_pictures_and_state();
        route_change();
        route_failures();
    }

    void set_limits() {
        server.new_task_queue = [] { return new httplib::ThreadPool(kWorkers); };
        server.set_payload_max_length(options.max_request_bytes);
        server.set_read_timeout(2, 0);  // a client that stops sending mid-request is dropped, not waited for
        server.set_write_timeout(5, 0);
        server.set_keep_alive_max_count(100);
        server.set_pre_routing_handler(screen);
    }

    // What the page reads: the page itself, the view's state, its pictures and their read-outs.
    void route_pictures_and_state() {
        server.Get("/", [](const httplib::Request&, httplib::Response& res) {
            no_caching(res);
            res.set_content(view_page(), "text/html; charset=utf-8");
        });
        server.Get("/api/state", [this](const httplib::Request&, httplib::Response& res) {
            const std::lock_guard lock(mutex);
            no_caching(res);
            send_json(res, 200, view.state());
        });
        server.Get("/api/image.png", [this](const httplib::Request&, httplib::Response& res) {
            const std::lock_guard lock(mutex);
            no_caching(res);
            res.set_header("X-Version", std::to_string(view.version()));
            res.set_content(view.frame_png(), "image/png");
        });
        server.Get("/api/timeline.json", [this](const httplib::Request&, httplib::Response& res) {
            const std::lock_guard lock(mutex);
            no_caching(res);
            send_json(res, 200, view.timeline());
        });
        server.Get("/api/fidelity.json", [this](const httplib::Request&, httplib::Response& res) {
            const std::lock_guard lock(mutex);
            no_caching(res);
            send_json(res, 200, view.reference_fidelity());
        });
        server.Get("/api/tiles.png", [this](const httplib::Request&, httplib::Response& res) {
            const std::lock_guard lock(mutex);
            const std::optional<std::string> png = view.tile_map_png();
            if (!png) return send_error(res, 404, "tiles", "the last frame's kernel casts no screen tiles on GPs");
            no_caching(res);
            res.set_content(*png, "image/png");
        });
        // Every kernel on the view as it stands: seconds of rendering, so it is asked for, not fetched.
        server.Post("/api/compare", [this](const httplib::Request&, httplib::Response& res) {
            const std::lock_guard lock(mutex);
            no_caching(res);
            send_json(res, 200, view.compare_kernels());
        });
        server.Get(R"(/api/compare/([a-z0-9_-]{1,64})\.png)", [this](const httplib::Request& req,
                                                                     httplib::Response& res) {
            const std::lock_guard lock(mutex);
            const std::optional<std::string> png = view.comparison_png(req.matches[1].str());
            if (!png)
                return send_error(res, 404, "kernel", "the last comparison has no picture by " + req.matches[1].str());
            no_caching(res);
            res.set_content(*png, "image/png");
        });
        server.Get(R"(/api/pass/(\d{1,3})\.png)", [this](const httplib::Request& req, httplib::Response& res) {
            const std::lock_guard lock(mutex);
            const std::size_t pass = std::strtoul(req.matches[1].str().c_str(), nullptr, 10);
            if (pass >= view.pass_count())
                return send_error(res, 404, "pass", fmt::format("the last frame has {} passes", view.pass_count()));
            no_caching(res);
            res.set_content(view.pass_png(pass), "image/png");
        });
    }

    // The one request that changes the view. Its body is read here, piece by piece, so that the size
    // limit holds for a chunked body too (cpp-httplib enforces it only on a Content-Length).
    void route_change() {
        server.Post("/api/change", [this](const httplib::Request& req, httplib::Response& res,
                                          const httplib::ContentReader& read_body) {
            const std::string type = req.get_header_value("Content-Type");
            if (type.rfind("application/json", 0) != 0)
                return send_error(res, 415, "Content-Type", "a change is sent as application/json");
            std::string body;
            bool too_large = false;
            const bool read = read_body([&](const char* data, std::size_t length) {
                too_large = body.size() + length > options.max_request_bytes;
                if (!too_large) body.append(data, length);
                return !too_large;
            });
            // cpp-httplib refuses a Content-Length past the limit itself, with a 413 and no body.
            if (too_large || res.status == 413)
                return send_error(res, 413, "body", "the request is larger than the server accepts");
            if (!read) return send_error(res, 400, "body", "the body could not be read whole");
            nlohmann::json change;
            try {
                change = parse_json_input(body, "request", "body");
            } catch (const InputError& e) {
                return send_error(res, 400, "body", e.reason());
            }
            const std::lock_guard lock(mutex);
            try {
                view.apply(change);
            } catch (const InputError& e) {
                return send_error(res, 400, e.field(), e.reason());
            }
            no_caching(res);
            send_json(res, 200, view.state());
        });
    }

    // Every refusal and failure answers in the same JSON shape as the routes' own errors.
    void route_failures() {
        server.set_error_handler([](const httplib::Request& req, httplib::Response& res) {
            if (!res.body.empty()) return;
            if (res.status == 404) send_error(res, 404, "path", "nothing is served at " + req.path);
            else if (res.status == 413) send_error(res, 413, "body", "the request is larger than the server accepts");
            else send_error(res, res.status, "request", "refused");
        });
        server.set_exception_handler([](const httplib::Request&, httplib::Response& res, std::exception_ptr error) {
            std::string what = "unknown error";
            try {
                std::rethrow_exception(error);
            } catch (const std::exception& e) {
                what = e.what();
            } catch (...) {}
            send_error(res, 500, "", "internal error: " + what);
        });
    }
};

ViewServer::ViewServer(InteractiveView& view, ServeOptions options)
    : impl_(std::make_unique<Impl>(view, std::move(options))) {}
ViewServer::~ViewServer() = default;

int ViewServer::bind() {
    const auto& o = impl_->options;
    if (o.port < 0 || o.port > 65535) throw InputError("--port", "--port", "a port is 0 (any free one) to 65535");
    if (o.port == 0) {
        impl_->port = impl_->server.bind_to_any_port(o.host);
    } else {
        impl_->port = impl_->server.bind_to_port(o.host, o.port) ? o.port : -1;
    }
    if (impl_->port < 0)
        throw InputError(
            o.port == 0 ? "--host" : "--port", o.port == 0 ? "--host" : "--port",
            fmt::format("cannot listen on {}:{} (in use, or not an address of this computer)", o.host, o.port));
    return impl_->port;
}

void ViewServer::serve() { impl_->server.listen_after_bind(); }

void ViewServer::stop() { impl_->server.stop(); }

}  // namespace pp5
