// `pp5sim serve`'s HTTP side, in process on a free loopback port: the page and the API answer, a
// change renders a new picture, and malformed, oversized, misdirected and concurrent requests are
// answered with the right status and never break the server.

#include "frontends/serve/view_server.h"
#include "kernels/registry/run_config.h"

#include <gtest/gtest.h>
#include <httplib.h>

#include <filesystem>
#include <fstream>
#include <thread>
#include <unistd.h>

namespace pp5 {
namespace {

namespace fs = std::filesystem;

Scenario tiny_scenario() {
    const fs::path file = fs::temp_directory_path() / ("pp5_server_test_" + std::to_string(getpid()) + ".toml");
    std::ofstream(file) << "[scenario]\nname = \"server-test\"\n[dataset]\nphantom = \"sphere\"\nsize = 24\n[image]\nwidth = 32\nheight = 32\n"
                           "[classification]\nkind = \"piecewise-linear\"\npoints = [{ value = 50.0, opacity = 0.0 }, { value = 150.0, opacity = 0.8 }]\n"
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
    httplib::Result change(const std::string& body, const char* type = "application/json") const { return client().Post("/api/change", body, type); }

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
    EXPECT_EQ(client().Get("/api/change")->status, 405);
    EXPECT_EQ(client().Delete("/api/state")->status, 405);
    // Still serving, and nothing changed.
    auto state = client().Get("/api/state");
    ASSERT_TRUE(state);
    EXPECT_EQ(nlohmann::json::parse(state->body)["version"], 1);
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
