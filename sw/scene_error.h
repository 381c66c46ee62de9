// Bad input: the message is one line naming where and what ("file:12: ...").
#pragma once
#include <stdexcept>
#include <string>

namespace rt {

struct SceneError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

}  // namespace rt
