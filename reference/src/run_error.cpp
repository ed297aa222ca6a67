#include <string>

#include "lockstep/world.hpp"

namespace lockstep {

RunError::RunError(int frame_, int body_, std::string quantity_, const std::string& what)
    : std::runtime_error("frame " + std::to_string(frame_) + (body_ >= 0 ? ", body " + std::to_string(body_) : std::string()) +
                         ", " + quantity_ + ": " + what),
      frame(frame_), body(body_), quantity(std::move(quantity_)) {}

}  // namespace lockstep
