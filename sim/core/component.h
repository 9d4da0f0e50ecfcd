#pragma once
// A component of the simulated machine: a hierarchical name ("gp[7]", "ring.channel[2]"), its
// statistics and its children. Components are built once by the machine and never move.

#include "sim/core/statistics.h"

#include <nlohmann/json_fwd.hpp>

#include <string>
#include <vector>

namespace pp5 {

class Component {
public:
    // `local_name` is this component's part of the path ("channel[2]"); the parent's path is prepended.
    Component(std::string local_name, Component* parent);
    virtual ~Component() = default;
    Component(const Component&) = delete;
    Component& operator=(const Component&) = delete;

    const std::string& name() const { return name_; }
    Component* parent() const { return parent_; }
    const std::vector<Component*>& children() const { return children_; }
    StatGroup& stats() { return stats_; }
    const StatGroup& stats() const { return stats_; }

    // Statistics of this component and all below it, keyed by full name, in a flat object.
    void collect_stats(nlohmann::json& out) const;
    void reset_stats();

    static std::string indexed(const std::string& base, std::size_t index) {
        return base + "[" + std::to_string(index) + "]";
    }

private:
    std::string name_;
    Component* parent_;
    std::vector<Component*> children_;
    StatGroup stats_;
};

}  // namespace pp5
