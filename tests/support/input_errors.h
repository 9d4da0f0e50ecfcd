#pragma once
// The InputError a piece of code throws, for tests of how bad input is refused.

#include "sim/core/input_error.h"

#include <gtest/gtest.h>

namespace pp5::test {

// Runs `load` and returns the InputError it throws; fails the test if it throws nothing.
template <class Fn>
InputError input_error_from(Fn&& load) {
    try {
        load();
    } catch (const InputError& e) {
        return e;
    }
    ADD_FAILURE() << "expected an InputError";
    return InputError("", "", "no error");
}

}  // namespace pp5::test
