// `pp5sim serve [SCENARIO]`: a page in the browser that shows the simulated machine's picture and lets a
// user orbit the eye, move the light, move and resize the volume of interest and change its opacity,
// and choose another kernel, showing after each change the simulated times and frame rate, what the
// change recomputed, and how busy the GPs, renderers and ring were. One scenario on one machine, kept
// running: each change is the next frame (frontends/serve). Bound to 127.0.0.1 unless told otherwise.

#include "frontends/cli/commands.h"
#include "frontends/serve/interactive_view.h"
#include "frontends/serve/view_server.h"
#include "kernels/registry/run_config.h"
#include "scene/scenario/scenario.h"
#include "sim/core/input_error.h"

#include <fmt/core.h>

#include <pthread.h>
#include <csignal>
#include <cstdio>
#include <thread>

namespace pp5::cli {
namespace {

struct ServeCommandOptions {
    std::string scenario = "mr-head-region";
    std::string machine = "pxpl5";
    std::vector<std::string> overrides;
    std::string host = "127.0.0.1";
    int port = 8059;
    int image_size = 0;  // 0: the scenario's
};

int run_serve(const ServeCommandOptions& o) {
    Scenario scenario = load_scenario(resolve_scenario_file(o.scenario));
    const MachineConfig config = load_run_config(o.machine, o.overrides);
    if (o.image_size != 0) {
        if (o.image_size < 16 || o.image_size > 2048)
            throw InputError("--image-size", "--image-size", "a picture is 16 to 2048 pixels square");
        scenario.image.width = scenario.image.height = o.image_size;
    }
    if (o.port > 65535) throw InputError("--port", "--port", "a port is 0 (any free one) to 65535");
    ServeOptions options;
    options.host = o.host;
    options.port = o.port;

    // SIGINT and SIGTERM end the server from a thread of their own (a handler may not stop it safely).
    sigset_t stop_signals;
    sigemptyset(&stop_signals);
    sigaddset(&stop_signals, SIGINT);
    sigaddset(&stop_signals, SIGTERM);
    pthread_sigmask(SIG_BLOCK, &stop_signals, nullptr);

    fmt::print("pp5sim serve: rendering the first frame of {}...\n", scenario.name);
    std::fflush(stdout);
    InteractiveView view(std::move(scenario), config);
    ViewServer server(view, options);
    const int port = server.bind();
    fmt::print("pp5sim serve: open http://{}:{}/ (Ctrl-C stops)\n", o.host, port);
    std::fflush(stdout);
    std::thread waiter([&] {
        int signal = 0;
        sigwait(&stop_signals, &signal);
        server.stop();
    });
    server.serve();
    // serve() may also end on its own (the socket failed): release the waiting thread.
    pthread_kill(waiter.native_handle(), SIGTERM);
    waiter.join();
    fmt::print("pp5sim serve: stopped\n");
    return 0;
}

}  // namespace

void add_serve_command(CLI::App& app, std::function<int()>& run) {
    auto o = std::make_shared<ServeCommandOptions>();
    CLI::App* cmd =
        app.add_subcommand("serve", "Show a scenario in the browser and change the eye, light, region and kernel live");
    cmd->add_option("scenario", o->scenario, "Scenario file (TOML) or the name of a shipped one")
        ->capture_default_str();
    cmd->add_option("--machine", o->machine, "Machine file or preset name")->capture_default_str();
    cmd->add_option("--set", o->overrides, "Override a machine parameter, key=value (repeatable; see `pp5sim params`)");
    cmd->add_option("--host", o->host, "Address to listen on (127.0.0.1: this computer only)")->capture_default_str();
    cmd->add_option("--port", o->port, "Port to listen on; 0 picks a free one")
        ->check(whole_number())
        ->capture_default_str();
    cmd->add_option("--image-size", o->image_size,
                    "Render N x N pictures instead of the scenario's size (smaller is quicker)")
        ->check(whole_number());
    cmd->callback([o, &run] { run = [o] { return run_serve(*o); }; });
}

}  // namespace pp5::cli
