// Exception types of the core library. The ROS layer maps each to a status code.
#pragma once

#include <stdexcept>
#include <string>

namespace occlusion_env {

/// `text` in single quotes for an error message, cut to `max_chars` (requests may carry very long
/// strings; messages stay readable). Control characters are escaped (\0, \n, \xNN): a NUL would
/// otherwise end the message where what() is read as a C string.
std::string quoted(const std::string& text, std::size_t max_chars = 64);

/// A caller passed a value the core cannot accept (bad option, non-finite action, unknown id).
class InvalidArgumentError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

/// A call came at the wrong time (e.g. step() before any reset()).
class InvalidStateError : public std::logic_error {
 public:
  using std::logic_error::logic_error;
};

/// An object source could not be read (missing, truncated or corrupt file); the message names it.
class CatalogError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The renderer failed (no GL context, framebuffer incomplete, shader error).
class RenderError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// No scene with visible occlusion was found within the allowed number of draws.
class SceneGenerationError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The environment cannot be reached (a remote simulator or camera that went away or never came):
/// the request may not have been carried out. Nothing about the request itself was wrong.
class EnvironmentUnavailableError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The camera is there but its view cannot be used: too little valid depth in the working range
/// (a covered lens, a camera too close, a reflective or empty scene). No estimate is made from
/// it, so it can never pass for a clear view. The ROS layer answers it UNAVAILABLE, as any
/// EnvironmentUnavailableError; an episode runner ends the episode on it as a failure
/// (EpisodeEnd::kUnusableView) and goes on with the next.
class UnusableViewError : public EnvironmentUnavailableError {
 public:
  using EnvironmentUnavailableError::EnvironmentUnavailableError;
};

}  // namespace occlusion_env
