// Maps the core's exception types to the Status codes every response carries.
#pragma once

#include <exception>
#include <string>

#include "occlusion_env/Status.h"

namespace occlusion_env {

/// A Status message with `code` and `message`.
Status makeStatus(std::uint8_t code, const std::string& message = "");

/// The Status describing `error` (InvalidArgumentError -> INVALID_ARGUMENT, and so on; anything
/// else -> INTERNAL_ERROR). Call from a catch block with std::current_exception().
Status statusFromException(const std::exception_ptr& error);

/// The inverse of statusFromException for a client: returns for OK, else throws the core's
/// exception type of `status.code` (INVALID_ARGUMENT -> InvalidArgumentError, ...,
/// INTERNAL_ERROR and unknown codes -> std::runtime_error) with `what` and the message.
void throwForStatus(const Status& status, const std::string& what);

/// Runs `action`; returns OK, or the status of whatever it threw.
template <typename Action>
Status runWithStatus(Action&& action) {
  try {
    action();
    return makeStatus(Status::OK);
  } catch (...) {
    return statusFromException(std::current_exception());
  }
}

}  // namespace occlusion_env
