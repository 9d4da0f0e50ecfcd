// `pp5sim serve`'s request handling: each input is sent as raw bytes to a server running in this
// process on a loopback port (the screening, the routes, the change parser and the view it changes),
// and the answer is read back. A crash, a sanitizer report or an exception escaping a handler aborts
// the run; every answer must be a status line, and the server must still answer a valid request.
#include "frontends/serve/view_server.h"
#include "kernels/registry/run_config.h"
#include "tests/fuzz/fuzz_input.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <string>
#include <thread>

namespace {

// One server for the whole run, on a tiny scenario so that a valid change renders quickly.
struct Harness {
    std::unique_ptr<pp5::InteractiveView> view;
    std::unique_ptr<pp5::ViewServer> server;
    std::thread thread;
    int port = 0;

    Harness() {
        const auto file = pp5::fuzz::scratch_directory() / "http-scenario.toml";
        std::ofstream(file)
            << "[scenario]\nname = \"fuzz-http\"\n[dataset]\nphantom = \"sphere\"\nsize = 16\n[image]\nwidth = "
               "16\nheight = 16\n"
               "[classification]\nkind = \"piecewise-linear\"\npoints = [{ value = 50.0, opacity = 0.0 }, "
               "{ value = 150.0, opacity = 0.8 }]\n";
        view = std::make_unique<pp5::InteractiveView>(pp5::load_scenario(file), pp5::load_run_config("pxpl5", {}));
        pp5::ServeOptions options;
        options.port = 0;
        server = std::make_unique<pp5::ViewServer>(*view, options);
        port = server->bind();
        thread = std::thread([this] { server->serve(); });
        thread.detach();  // runs until the process ends
    }
};

// Never destroyed: the server's thread is still listening when the process exits, and tearing the
// server down under it would race with it.
Harness& harness() {
    static Harness* h = new Harness;
    return *h;
}

// Sends `data` and returns what the server answers within `wait_ms` of its last byte. The sending
// side is left open (cpp-httplib 0.11 writes no answer to a client that has half-closed), so a request
// the input leaves unfinished is simply abandoned when the wait runs out: closing the socket ends the
// server's read at once. libFuzzer's -timeout arms a SIGALRM every timeout/2 + 1 seconds, and poll is
// never restarted after a signal: an interrupted call is retried for what is left of the wait, or an
// answer still on its way would be read as none.
std::string exchange(int port, const std::uint8_t* data, std::size_t size, int wait_ms) {
    const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
    if (fd < 0) std::abort();
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_port = htons(static_cast<std::uint16_t>(port));
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    // An interrupted connect goes on in the background, and Linux's TCP send waits for it to finish.
    if (::connect(fd, reinterpret_cast<const sockaddr*>(&address), sizeof address) != 0 && errno != EINTR) std::abort();
    for (std::size_t sent = 0; sent < size;) {
        const ssize_t n = ::send(fd, data + sent, size - sent, MSG_NOSIGNAL);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) break;  // the server may close early on a refused request
        sent += static_cast<std::size_t>(n);
    }
    std::string answer;
    char buffer[4096];
    using Clock = std::chrono::steady_clock;
    auto deadline = Clock::now() + std::chrono::milliseconds(wait_ms);
    while (true) {
        const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
        if (left <= 0) break;
        pollfd readable{fd, POLLIN, 0};
        const int ready = ::poll(&readable, 1, static_cast<int>(left));
        if (ready < 0 && errno == EINTR) continue;
        if (ready <= 0) break;
        const ssize_t n = ::recv(fd, buffer, sizeof buffer, 0);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) break;
        answer.append(buffer, static_cast<std::size_t>(n));
        deadline = Clock::now() + std::chrono::milliseconds(wait_ms);  // the wait runs from the last byte
    }
    ::close(fd);
    return answer;
}

[[noreturn]] void finding(const char* what, const std::string& answer) {
    std::fprintf(stderr, "fuzz_http: %s: \"%s\"\n", what, answer.substr(0, 200).c_str());
    std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const int port = harness().port;
    // A finished request is answered in a few milliseconds (a change renders a 16x16 frame).
    const std::string answer = exchange(port, data, size, 50);
    // Whatever came back is HTTP (or nothing, for a connection closed on a malformed request).
    if (!answer.empty() && answer.rfind("HTTP/1.1 ", 0) != 0) finding("an answer that is not HTTP", answer);
    // The input's change may still be rendering (it was abandoned after 50 ms), and the state waits for
    // it: under the sanitizers a change of kernel or machine takes seconds. A server that stops
    // answering still shows, within libFuzzer's 30 s limit on one input.
    static const std::uint8_t kValid[] = "GET /api/state HTTP/1.1\r\nHost: fuzz\r\nConnection: close\r\n\r\n";
    if (const std::string after = exchange(port, kValid, sizeof kValid - 1, 20000); after.rfind("HTTP/1.1 200", 0) != 0)
        finding("a valid request afterwards not answered 200", after);
    return 0;
}
