// Runs a callable that must throw npf::Error and returns its message, so that tests can check
// what the message names; records a test failure (and returns "") when nothing is thrown.
#pragma once

#include <npf/core/error.h>

#include <gtest/gtest.h>

#include <string>

namespace npf::testing {

template <class F>
std::string error_of(F&& f) {
    try {
        f();
    } catch (const npf::Error& e) {
        return e.what();
    }
    ADD_FAILURE() << "no npf::Error thrown";
    return "";
}

}  // namespace npf::testing
