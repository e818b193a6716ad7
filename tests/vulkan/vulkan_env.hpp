// Shared by the Vulkan tests: one context on the first compute device, with the validation
// layer when installed and a debug-utils messenger that turns every validation warning or error
// into a test failure. Without a device, tests skip with the reason (never pass silently).
#pragma once
#include <gtest/gtest.h>

#include <cstdlib>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "frnn/vulkan.hpp"

namespace frnn::vulkan::test {

struct messages {
    std::mutex mutex;
    std::vector<std::string> list;
    void add(severity s, const std::string& m) {
        if (s != severity::warning && s != severity::error) return;
        std::lock_guard lock(mutex);
        list.push_back((s == severity::error ? "error: " : "warning: ") + m);
    }
    std::vector<std::string> take() {
        std::lock_guard lock(mutex);
        return std::exchange(list, {});
    }
};

inline messages& validation_messages() {
    static messages m;
    return m;
}

bool validation_layer_installed();

/// Options of every test context: validation when installed, messages collected.
context_options test_options();

/// The shared context, or nullptr with `why` set when no Vulkan device can be used.
context* shared_context(std::string* why = nullptr);

/// The message of the frnn::error that f() throws, or a text saying none was thrown.
template <class F>
std::string error_of(F&& f) {
    try {
        f();
    } catch (const frnn::error& e) {
        return e.what();
    }
    return "(no frnn::error thrown)";
}

/// Whether FRNN_STRICT=1 (CI): then a missing device fails the tests instead of skipping them,
/// so that a regression in creating the context cannot read as "no device".
inline bool strict_mode() {
    const char* s = std::getenv("FRNN_STRICT");
    return s && std::string(s) == "1";
}

/// Base fixture: skips without a device (fails under FRNN_STRICT=1); fails a test that
/// produced validation messages.
class vulkan_test : public ::testing::Test {
protected:
    void SetUp() override {
        std::string why;
        ctx_ = shared_context(&why);
        // Messages so far come from creating the context (the loader's, when it fails).
        const auto early = validation_messages().take();
        if (!ctx_) {
            for (const auto& m : early) why += "; " + m;
            if (strict_mode()) FAIL() << "no Vulkan device, and FRNN_STRICT=1 requires one: " << why;
            GTEST_SKIP() << "no Vulkan device: " << why;
        }
    }
    void TearDown() override {
        for (const auto& m : validation_messages().take()) ADD_FAILURE() << "Vulkan validation " << m;
    }
    context& ctx() { return *ctx_; }
    context* ctx_ = nullptr;
};

}  // namespace frnn::vulkan::test
