#pragma once
// `pp5sim serve`'s HTTP side (cpp-httplib): the page, the view's state, its picture, and changes to it.
// Requests are served one at a time against one InteractiveView (a change renders a frame; two at once
// would race on the simulated machine). It reads no files: the page is built into the program, and
// pictures come from memory. A bad request gets a 4xx with a JSON {"error", "field", "reason"}.
//
//   GET  /                  the page
//   GET  /api/state         the view (settings, the last frame's times, rates, phases, utilisation)
//   GET  /api/image.png     the last frame's picture;  /api/pass/N.png  its refinement pass N
//   POST /api/change        a JSON change (docs/serve.md); answers with the new state

#include "frontends/serve/interactive_view.h"

#include <memory>
#include <string>

namespace pp5 {

struct ServeOptions {
    std::string host = "127.0.0.1";
    int port = 8059;                        // 0: any free port
    std::size_t max_request_bytes = 65536;  // larger bodies get 413
};

class ViewServer {
public:
    ViewServer(InteractiveView& view, ServeOptions options);
    ~ViewServer();
    // Binds the socket; returns the port (InputError naming --port when it cannot bind).
    int bind();
    // Serves until stop() (from another thread).
    void serve();
    void stop();

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

// The page `GET /` serves (frontends/serve/page/index.html, built in).
const std::string& view_page();

}  // namespace pp5
