#include "sim/core/component.h"

#include <nlohmann/json.hpp>

namespace pp5 {

Component::Component(std::string local_name, Component* parent)
    : name_(parent ? parent->name() + "." + local_name : std::move(local_name)), parent_(parent) {
    if (parent_) parent_->children_.push_back(this);
}

void Component::collect_stats(nlohmann::json& out) const {
    if (!stats_.all().empty()) out[name_] = stats_.to_json();
    for (const Component* child : children_) child->collect_stats(out);
}

void Component::reset_stats() {
    stats_.reset();
    for (Component* child : children_) child->reset_stats();
}

}  // namespace pp5
