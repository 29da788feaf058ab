#include "occlusion_env/ros/status.hpp"

#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/ros/parameters.hpp"

namespace occlusion_env {

Status makeStatus(std::uint8_t code, const std::string& message) {
  Status status;
  status.code = code;
  status.message = message;
  return status;
}

void throwForStatus(const Status& status, const std::string& what) {
  const std::string message = what + ": " + status.message;
  switch (status.code) {
    case Status::OK:
      return;
    case Status::INVALID_ARGUMENT:
      throw InvalidArgumentError(message);
    case Status::INVALID_STATE:
      throw InvalidStateError(message);
    case Status::CATALOG_ERROR:
      throw CatalogError(message);
    case Status::RENDER_ERROR:
      throw RenderError(message);
    case Status::SCENE_GENERATION_ERROR:
      throw SceneGenerationError(message);
    case Status::UNAVAILABLE:
      throw EnvironmentUnavailableError(message);
    default:
      throw std::runtime_error(message + " (status " + std::to_string(status.code) + ")");
  }
}

Status statusFromException(const std::exception_ptr& error) {
  // Most specific types first: ParameterError and InvalidArgumentError are invalid_arguments.
  try {
    std::rethrow_exception(error);
  } catch (const InvalidArgumentError& e) {
    return makeStatus(Status::INVALID_ARGUMENT, e.what());
  } catch (const ParameterError& e) {
    return makeStatus(Status::INVALID_ARGUMENT, e.what());
  } catch (const InvalidStateError& e) {
    return makeStatus(Status::INVALID_STATE, e.what());
  } catch (const CatalogError& e) {
    return makeStatus(Status::CATALOG_ERROR, e.what());
  } catch (const RenderError& e) {
    return makeStatus(Status::RENDER_ERROR, e.what());
  } catch (const SceneGenerationError& e) {
    return makeStatus(Status::SCENE_GENERATION_ERROR, e.what());
  } catch (const EnvironmentUnavailableError& e) {
    return makeStatus(Status::UNAVAILABLE, e.what());
  } catch (const std::exception& e) {
    return makeStatus(Status::INTERNAL_ERROR, std::string("internal error: ") + e.what());
  } catch (...) {
    return makeStatus(Status::INTERNAL_ERROR, "internal error: unknown exception");
  }
}

}  // namespace occlusion_env
