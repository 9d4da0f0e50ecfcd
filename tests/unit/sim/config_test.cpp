#include "sim/core/config.h"
#include "sim/core/input_error.h"
#include "sim/machine/machine.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>

namespace pp5 {
namespace {

namespace fs = std::filesystem;

fs::path write_temp(const std::string& name, const std::string& text) {
    const fs::path path = fs::temp_directory_path() / ("pp5_config_test_" + name);
    std::ofstream(path) << text;
    return path;
}

// Runs `body`, expecting an InputError that names `file` and `field`, and returns its reason.
template <class F>
std::string expect_input_error(F body, const std::string& file, const std::string& field) {
    try {
        body();
    } catch (const InputError& e) {
        EXPECT_EQ(e.file(), file);
        EXPECT_EQ(e.field(), field);
        return e.reason();
    }
    ADD_FAILURE() << "expected an InputError for " << field;
    return {};
}

TEST(MachineConfig, DefaultsAreLevoysMachine) {
    const MachineConfig config = Machine::default_config();
    EXPECT_EQ(config.integer("gp.count"), 32);
    EXPECT_EQ(config.integer("renderer.count"), 16);
    EXPECT_EQ(config.integer("renderer.backing_store_bits"), 4096);
    EXPECT_EQ(config.integer("renderer.local_memory_bits"), 208);
    EXPECT_EQ(config.integer("ring.channels"), 8);
    EXPECT_DOUBLE_EQ(config.real("ring.clock_mhz"), 20.0);
}

TEST(MachineConfig, EveryParameterIsDocumented) {
    for (const ParamGroup* group : Machine::param_groups()) {
        for (const ParamSpec& spec : group->specs()) {
            EXPECT_FALSE(spec.doc.empty()) << group->prefix() << "." << spec.name;
            EXPECT_FALSE(spec.source.empty()) << group->prefix() << "." << spec.name;
            if (spec.type == ParamType::Integer || spec.type == ParamType::Real) {
                EXPECT_TRUE(spec.min && spec.max) << group->prefix() << "." << spec.name;
            }
        }
    }
}

TEST(MachineConfig, OverridesAreTypedAndRecorded) {
    MachineConfig config = Machine::default_config();
    config.apply_override("gp.count=64");
    config.apply_override("ring.clock_mhz=40");
    config.apply_override("ring.station_order=interleaved");
    EXPECT_EQ(config.integer("gp.count"), 64);
    EXPECT_DOUBLE_EQ(config.real("ring.clock_mhz"), 40.0);
    EXPECT_EQ(config.text("ring.station_order"), "interleaved");
    EXPECT_EQ(config.to_json()["parameters"]["gp.count"]["origin"], "--set");
}

// What re-timing checks before it re-times recorded work: only the values that differ, in key order.
TEST(MachineConfig, NamesTheKeysWhoseValuesDiffer) {
    const MachineConfig base = Machine::default_config();
    MachineConfig other = base;
    EXPECT_TRUE(other.keys_differing_from(base).empty());
    other.apply_override("ring.clock_mhz=7");
    other.apply_override("gp.count=64");
    other.apply_override("gp.count=32");  // back to the base's value: not a difference
    other.apply_override("renderer.backing_store_bits=8192");
    EXPECT_EQ(other.keys_differing_from(base),
              (std::vector<std::string>{"renderer.backing_store_bits", "ring.clock_mhz"}));
    EXPECT_EQ(base.keys_differing_from(other), other.keys_differing_from(base));
    EXPECT_EQ(std::get<std::int64_t>(other.value("renderer.backing_store_bits")), 8192);
}

TEST(MachineConfig, BadOverridesNameTheKeyAndReason) {
    MachineConfig config = Machine::default_config();
    std::string why = expect_input_error([&] { config.apply_override("gp.cuont=3"); }, "--set", "gp.cuont");
    EXPECT_NE(why.find("did you mean gp.count"), std::string::npos) << why;
    why = expect_input_error([&] { config.apply_override("gp.count=0"); }, "--set", "gp.count");
    EXPECT_NE(why.find("outside the allowed range"), std::string::npos) << why;
    why = expect_input_error([&] { config.apply_override("gp.count=many"); }, "--set", "gp.count");
    EXPECT_NE(why.find("not a valid integer"), std::string::npos) << why;
    expect_input_error([&] { config.apply_override("ring.station_order=random"); }, "--set", "ring.station_order");
    expect_input_error([&] { config.apply_override("noequals"); }, "--set", "noequals");
    expect_input_error([&] { config.apply_override("ring.clock_mhz=nan"); }, "--set", "ring.clock_mhz");
}

TEST(MachineConfig, BadMachineFilesNameTheFileKeyAndReason) {
    MachineConfig config = Machine::default_config();
    auto path = write_temp("unknown.toml", "[gp]\ncount = 32\nclock_hz = 4\n");
    expect_input_error([&] { config.load_file(path); }, path.string(), "gp.clock_hz");

    path = write_temp("range.toml", "[renderer]\ncount = -1\n");
    expect_input_error([&] { config.load_file(path); }, path.string(), "renderer.count");

    path = write_temp("type.toml", "[ring]\nchannels = \"eight\"\n");
    std::string why = expect_input_error([&] { config.load_file(path); }, path.string(), "ring.channels");
    EXPECT_NE(why.find("integer"), std::string::npos);

    path = write_temp("syntax.toml", "[ring\nchannels = 8\n");
    expect_input_error([&] { config.load_file(path); }, path.string(), "line 1, column 6");

    path = write_temp("notable.toml", "gp = 3\n");
    expect_input_error([&] { config.load_file(path); }, path.string(), "gp");
}

// Keys nested thousands deep (dotted keys, table headers, inline tables) would overflow the stack in
// the TOML library: refused before parsing, naming the line; strings and comments with dots are not keys.
TEST(MachineConfig, KeysNestedDeeperThanAnyParameterAreRefusedBeforeParsing) {
    MachineConfig config = Machine::default_config();
    std::string deep;
    for (int i = 0; i < 20000; ++i) deep += "a.";
    for (const std::string& text :
         {"[gp]\ncount = 32\n" + deep + "b = 1\n", "[" + deep + "b]\n", "x = { " + deep + "b = 1 }\n"}) {
        const auto path = write_temp("deep.toml", text);
        const std::string why = expect_input_error([&] { config.load_file(path); }, path.string(),
                                                   text.starts_with("[gp]") ? "line 3" : "line 1");
        EXPECT_NE(why.find("20001 dotted parts"), std::string::npos) << why;
    }
    const auto fine =
        write_temp("dots.toml", "[machine]\nname = \"a.b.c.d.e.f.g.h\" # " + deep + "\n[gp]\nclock_mhz = 40.0\n");
    EXPECT_NO_THROW(config.load_file(fine));
}

// A machine whose renderers' backing stores would not fit this computer (here 35 TB of them) is refused
// before any is allocated, saying what it would need, rather than dying of std::bad_alloc.
TEST(Machine, ThatCannotFitThisComputerIsRefusedBeforeItIsBuilt) {
    MachineConfig config = Machine::default_config();
    config.apply_override("renderer.count=1024");
    config.apply_override("renderer.backing_store_bits=16777216");
    const std::string why = expect_input_error([&] { Machine machine(config); }, "--set", "renderer.count");
    EXPECT_NE(why.find("GB of this computer's memory"), std::string::npos) << why;
}

TEST(MachineConfig, ResolvesPresetNames) {
    EXPECT_EQ(resolve_machine_file("pxpl5").filename(), "pxpl5.toml");
    EXPECT_THROW(resolve_machine_file("no-such-machine"), InputError);
}

TEST(Machine, AssemblesTheConfiguredComponents) {
    MachineConfig config = Machine::default_config();
    config.apply_override("gp.count=4");
    config.apply_override("renderer.count=2");
    Machine machine(config);
    EXPECT_EQ(machine.gps().size(), 4u);
    EXPECT_EQ(machine.renderers().size(), 2u);
    EXPECT_EQ(machine.gps()[3]->name(), "gp[3]");
    EXPECT_EQ(machine.gps()[0]->clock().period(), 25'000);
    EXPECT_EQ(machine.renderers()[1]->pixel_processors(), 128u * 128u);
    // host, 4 GPs, 2 renderers, frame buffer
    EXPECT_EQ(machine.ring().stations().size(), 8u);
    EXPECT_EQ(machine.ring().stations().front().name, "host");
    EXPECT_EQ(machine.ring().stations().back().name, "frame_buffer");

    const nlohmann::json stats = machine.statistics();
    EXPECT_TRUE(stats.contains("gp[3]"));
    EXPECT_TRUE(stats.contains("ring.channel[7]"));
    EXPECT_DOUBLE_EQ(stats["ring"]["peak_bandwidth"]["value"].get<double>(), 8 * 32 * 20e6);
}

TEST(RingNetwork, HopsGoDownstreamAroundTheRing) {
    MachineConfig config = Machine::default_config();
    config.apply_override("gp.count=4");
    config.apply_override("renderer.count=2");
    config.apply_override("ring.station_order=interleaved");
    Machine machine(config);
    const RingNetwork& ring = machine.ring();
    // host, renderer[0], gp[0], gp[1], renderer[1], gp[2], gp[3], frame_buffer
    EXPECT_EQ(ring.stations()[1].name, "renderer[0]");
    EXPECT_EQ(ring.stations()[2].name, "gp[0]");
    EXPECT_EQ(ring.stations()[4].name, "renderer[1]");
    const std::size_t gp0 = ring.position(StationKind::GraphicsProcessor, 0);
    const std::size_t r0 = ring.position(StationKind::Renderer, 0);
    EXPECT_EQ(ring.hops(r0, gp0), 1u);
    EXPECT_EQ(ring.hops(gp0, r0), ring.stations().size() - 1);
}

}  // namespace
}  // namespace pp5
