// Checks that a call fails with frnn::error and a message holding the expected parts (what and
// where), for any test folder.
#pragma once
#include <gtest/gtest.h>

#include <initializer_list>
#include <string>
#include <string_view>

#include "frnn/error.hpp"

namespace frnn::test {

/// Expects f() to throw frnn::error whose message contains every part.
template <class F>
void expect_error(F&& f, std::initializer_list<std::string_view> parts) {
    try {
        f();
        ADD_FAILURE() << "no frnn::error thrown";
    } catch (const frnn::error& e) {
        const std::string what = e.what();
        for (std::string_view p : parts)
            EXPECT_NE(what.find(p), std::string::npos) << "message '" << what << "' lacks '" << p << "'";
    }
}

}  // namespace frnn::test
