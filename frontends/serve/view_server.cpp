#include "frontends/serve/view_server.h"

#include "sim/core/input_error.h"
#include "sim/core/json_input.h"

#include <fmt/core.h>
#include <httplib.h>

#include <cstdlib>
#include <exception>
#include <mutex>

namespace pp5 {

namespace {

void send_json(httplib::Response& response, int status, const nlohmann::json& body) {
    response.status = status;
    response.set_content(body.dump(), "application/json");
}

void send_error(httplib::Response& response, int status, const std::string& field, const std::string& reason) {
    send_json(response, status, {{"error", field.empty() ? reason : field + ": " + reason}, {"field", field}, {"reason", reason}});
}

void no_caching(httplib::Response& response) { response.set_header("Cache-Control", "no-store"); }

}  // namespace

struct ViewServer::Impl {
    InteractiveView& view;
    ServeOptions options;
    httplib::Server server;
    std::mutex mutex;  // one request at a time touches the view
    int port = -1;

    Impl(InteractiveView& v, ServeOptions o) : view(v), options(std::move(o)) {
        server.set_payload_max_length(options.max_request_bytes);
        server.set_read_timeout(5, 0);  // a client that stops sending mid-request is dropped, not waited for
        server.set_write_timeout(5, 0);
        server.set_keep_alive_max_count(100);

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
        server.Get(R"(/api/pass/(\d{1,3})\.png)", [this](const httplib::Request& req, httplib::Response& res) {
            const std::lock_guard lock(mutex);
            const std::size_t pass = std::strtoul(req.matches[1].str().c_str(), nullptr, 10);
            if (pass >= view.pass_count())
                return send_error(res, 404, "pass", fmt::format("the last frame has {} passes", view.pass_count()));
            no_caching(res);
            res.set_content(view.pass_png(pass), "image/png");
        });
        server.Post("/api/change", [this](const httplib::Request& req, httplib::Response& res) {
            const std::string type = req.get_header_value("Content-Type");
            if (type.rfind("application/json", 0) != 0)
                return send_error(res, 415, "Content-Type", "a change is sent as application/json");
            nlohmann::json change;
            try {
                change = parse_json_input(req.body, "request", "body");
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
        // The paths exist, but not for this method.
        const auto not_allowed = [](const httplib::Request& req, httplib::Response& res) {
            send_error(res, 405, "method", req.method + " is not served here");
        };
        server.Post("/api/state", not_allowed);
        server.Post("/api/image.png", not_allowed);
        server.Get("/api/change", not_allowed);
        server.Put(".*", not_allowed);
        server.Delete(".*", not_allowed);
        server.Patch(".*", not_allowed);
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
            } catch (...) {
            }
            send_error(res, 500, "", "internal error: " + what);
        });
    }
};

ViewServer::ViewServer(InteractiveView& view, ServeOptions options) : impl_(std::make_unique<Impl>(view, std::move(options))) {}
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
        throw InputError(o.port == 0 ? "--host" : "--port", o.port == 0 ? "--host" : "--port",
                         fmt::format("cannot listen on {}:{} (in use, or not an address of this computer)", o.host, o.port));
    return impl_->port;
}

void ViewServer::serve() { impl_->server.listen_after_bind(); }

void ViewServer::stop() { impl_->server.stop(); }

}  // namespace pp5
