// `pp5sim serve`'s HTTP side, in process on a free loopback port: the page and the API answer, a
// change renders a new picture, and malformed, oversized, misdirected and concurrent requests are
// answered with the right status and never break the server.

#include "frontends/serve/view_server.h"
#include "kernels/registry/run_config.h"

#include <gtest/gtest.h>
#include <httplib.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>
#include <filesystem>
#include <fstream>
#include <thread>

namespace pp5 {
namespace {

namespace fs = std::filesystem;

Scenario tiny_scenario() {
    const fs::path file = fs::temp_directory_path() / ("pp5_server_test_" + std::to_string(getpid()) + ".toml");
    std::ofstream(file)
        << "[scenario]\nname = \"server-test\"\n[dataset]\nphantom = \"sphere\"\nsize = 24\n[image]\nwidth = "
           "32\nheight = 32\n"
           "[classification]\nkind = \"piecewise-linear\"\npoints = [{ value = 50.0, opacity = 0.0 }, { value = 150.0, "
           "opacity = 0.8 }]\n"
           "[shading]\nspecular = 0.0\nlight_direction = [0.4, 1.0, 0.5]\n[[frames]]\nlabel = \"first\"\n";
    Scenario s = load_scenario(file);
    fs::remove(file);
    return s;
}

class ServerTest : public ::testing::Test {
protected:
    void SetUp() override {
        view = std::make_unique<InteractiveView>(tiny_scenario(), load_run_config("pxpl5", {}));
        ServeOptions options;
        options.port = 0;
        options.max_request_bytes = 4096;
        server = std::make_unique<ViewServer>(*view, options);
        port = server->bind();
        thread = std::thread([this] { server->serve(); });
    }
    void TearDown() override {
        server->stop();
        thread.join();
    }
    httplib::Client client() const {
        httplib::Client c("127.0.0.1", port);
        c.set_read_timeout(60, 0);
        return c;
    }
    httplib::Result change(const std::string& body, const char* type = "application/json") const {
        return client().Post("/api/change", body, type);
    }

    std::unique_ptr<InteractiveView> view;
    std::unique_ptr<ViewServer> server;
    int port = 0;
    std::thread thread;
};

TEST_F(ServerTest, ServesThePageTheStateAndThePicture) {
    auto c = client();
    auto page = c.Get("/");
    ASSERT_TRUE(page);
    EXPECT_EQ(page->status, 200);
    EXPECT_NE(page->body.find("/api/change"), std::string::npos);
    auto state = c.Get("/api/state");
    ASSERT_TRUE(state);
    EXPECT_EQ(state->status, 200);
    EXPECT_EQ(nlohmann::json::parse(state->body)["scenario"], "server-test");
    auto image = c.Get("/api/image.png");
    ASSERT_TRUE(image);
    EXPECT_EQ(image->get_header_value("Content-Type"), "image/png");
    EXPECT_EQ(image->body.substr(1, 3), "PNG");
    auto pass = c.Get("/api/pass/0.png");
    ASSERT_TRUE(pass);
    EXPECT_EQ(pass->status, 200);
    auto timeline = c.Get("/api/timeline.json");
    ASSERT_TRUE(timeline);
    EXPECT_EQ(timeline->status, 200);
    EXPECT_EQ(nlohmann::json::parse(timeline->body), view->timeline());
    auto tiles = c.Get("/api/tiles.png");
    ASSERT_TRUE(tiles);
    EXPECT_EQ(tiles->status, 200);
    EXPECT_EQ(tiles->body, view->tile_map_png().value());
    EXPECT_EQ(c.Post("/api/timeline.json", "", "text/plain")->status, 405);
    auto fidelity = c.Get("/api/fidelity.json");
    ASSERT_TRUE(fidelity);
    EXPECT_EQ(fidelity->status, 200);
    EXPECT_TRUE(nlohmann::json::parse(fidelity->body)["fidelity"]["psnr_db"].is_number());
}

TEST_F(ServerTest, AChangeAnswersWithTheNewFrameAndANewPicture) {
    const std::string before = client().Get("/api/image.png")->body;
    auto r = change(R"({"light": {"direction": [-0.6, 1.0, 0.3]}})");
    ASSERT_TRUE(r);
    ASSERT_EQ(r->status, 200) << r->body;
    const auto state = nlohmann::json::parse(r->body);
    EXPECT_EQ(state["frame"]["index"], 1);
    EXPECT_TRUE(state["frame"]["changed"]["lighting"].get<bool>());
    EXPECT_NE(client().Get("/api/image.png")->body, before);
}

TEST_F(ServerTest, RefusesBadRequestsWithAReasonAndKeepsServing) {
    struct Case {
        std::string body;
        const char* type;
        int status;
        std::string field;
    };
    const std::vector<Case> cases = {
        {"not json", "application/json", 400, "body"},
        {R"({"camera": {"azimuth": "east"}})", "application/json", 400, "camera.azimuth"},
        {R"({"camera": 1})", "application/json", 400, "camera"},
        {R"([1, 2, 3])", "application/json", 400, ""},
        {R"({"light": {}})", "text/plain", 415, "Content-Type"},
        {std::string(8192, '{'), "application/json", 413, "body"},
        {std::string(3000, '['), "application/json", 400, "body"},  // deep nesting: a parse error, not a crash
    };
    for (const Case& c : cases) {
        auto r = change(c.body, c.type);
        ASSERT_TRUE(r) << c.body.substr(0, 40);
        EXPECT_EQ(r->status, c.status) << c.body.substr(0, 40) << ": " << r->body;
        const auto error = nlohmann::json::parse(r->body);
        EXPECT_EQ(error["field"], c.field) << r->body;
        EXPECT_FALSE(error["reason"].get<std::string>().empty());
    }
    EXPECT_EQ(client().Get("/no/such/path")->status, 404);
    EXPECT_EQ(client().Get("/../../etc/passwd")->status, 404);
    EXPECT_EQ(client().Get("/api/pass/99.png")->status, 404);
    // A known path with a method it does not answer: 405, saying which it does.
    for (const auto& [method, path] : std::vector<std::pair<std::string, std::string>>{{"GET", "/api/change"},
                                                                                       {"DELETE", "/api/state"},
                                                                                       {"POST", "/"},
                                                                                       {"PUT", "/api/image.png"},
                                                                                       {"POST", "/api/pass/0.png"}}) {
        httplib::Request request;
        request.method = method;
        request.path = path;
        auto r = client().send(request);
        ASSERT_TRUE(r) << method << " " << path;
        EXPECT_EQ(r->status, 405) << method << " " << path << ": " << r->body;
        EXPECT_FALSE(r->get_header_value("Allow").empty()) << method << " " << path;
    }
    // A body that is not UTF-8 is a bad request whose reason can still be written.
    auto not_utf8 = change("{\"light\": \"\xff\xfe\"}");
    ASSERT_TRUE(not_utf8);
    EXPECT_EQ(not_utf8->status, 400) << not_utf8->body;
    EXPECT_TRUE(nlohmann::json::accept(not_utf8->body)) << not_utf8->body;
    // A body sent in chunks is read up to the same limit: a small change is served, a large one refused.
    const auto send_chunked = [&](const std::string& body) {
        return client().Post(
            "/api/change",
            [body](std::size_t offset, httplib::DataSink& sink) {
                if (offset < body.size()) {
                    const std::size_t piece = std::min<std::size_t>(1000, body.size() - offset);
                    sink.write(body.data() + offset, piece);
                } else {
                    sink.done();
                }
                return true;
            },
            "application/json");
    };
    auto small_chunked = send_chunked(R"({"camera": {"azimuth": "east"}})");
    ASSERT_TRUE(small_chunked);
    EXPECT_EQ(small_chunked->status, 400) << small_chunked->body;  // read whole and parsed: the change itself is wrong
    EXPECT_EQ(nlohmann::json::parse(small_chunked->body)["field"], "camera.azimuth") << small_chunked->body;
    // Over the limit (4096 bytes here) reading stops: a 413, unless the connection is cut first while the
    // client still sends; either way the change is not applied (the version is checked below).
    auto large_chunked = send_chunked(R"({"camera": {"azimuth": 15}, "padding": ")" + std::string(6000, 'x') + "\"}");
    if (large_chunked) {
        EXPECT_EQ(large_chunked->status, 413) << large_chunked->body;
    }
    // Far more header lines than a browser sends.
    httplib::Headers many;
    for (int i = 0; i < 500; ++i) many.emplace("X-Filler-" + std::to_string(i), "x");
    auto crowded = client().Get("/api/state", many);
    ASSERT_TRUE(crowded);
    EXPECT_EQ(crowded->status, 431) << crowded->body;
    // Still serving, and nothing changed.
    auto state = client().Get("/api/state");
    ASSERT_TRUE(state);
    EXPECT_EQ(nlohmann::json::parse(state->body)["version"], 1);
}

// Clients that open a connection and trickle a request (or send nothing) hold a worker each; more of
// them than the old pool's eight must not keep a valid request waiting.
TEST_F(ServerTest, SlowClientsDoNotKeepAValidRequestWaiting) {
    std::vector<int> slow;
    for (int i = 0; i < 16; ++i) {
        const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
        ASSERT_GE(fd, 0);
        sockaddr_in address{};
        address.sin_family = AF_INET;
        address.sin_port = htons(static_cast<std::uint16_t>(port));
        address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        ASSERT_EQ(::connect(fd, reinterpret_cast<const sockaddr*>(&address), sizeof address), 0);
        const std::string start = "GET /api/state HTTP/1.1\r\nHost: x\r\n";  // never finished
        ASSERT_EQ(::send(fd, start.data(), start.size(), 0), static_cast<ssize_t>(start.size()));
        slow.push_back(fd);
    }
    httplib::Client c("127.0.0.1", port);
    c.set_connection_timeout(3, 0);
    c.set_read_timeout(3, 0);  // the slow clients' requests are not timed out before this answers
    auto state = c.Get("/api/state");
    ASSERT_TRUE(state) << httplib::to_string(state.error());
    EXPECT_EQ(state->status, 200);
    for (const int fd : slow) ::close(fd);
}

TEST_F(ServerTest, ConcurrentChangesAreServedOneAtATime) {
    std::vector<std::thread> clients;
    std::vector<int> statuses(4, 0);
    for (int i = 0; i < 4; ++i)
        clients.emplace_back([&, i] {
            auto r = change(nlohmann::json{{"camera", {{"azimuth", 10.0 * (i + 1)}}}}.dump());
            statuses[static_cast<std::size_t>(i)] = r ? r->status : -1;
        });
    for (auto& t : clients) t.join();
    for (int s : statuses) EXPECT_EQ(s, 200);
    const auto state = nlohmann::json::parse(client().Get("/api/state")->body);
    EXPECT_EQ(state["version"], 5);  // the first frame and four changes, each whole
    EXPECT_EQ(state["frame"]["index"], 4);
}

}  // namespace
}  // namespace pp5
