#include "tumble_client/failure.h"

namespace tumble::client {

Failure server_failure(const tumble::v1::Error& error) {
  std::string code_name = tumble::v1::ErrorCode_Name(error.code());
  if (code_name.empty()) code_name = "code " + std::to_string(static_cast<int>(error.code()));
  std::string message = "server error " + code_name;
  if (!error.message().empty()) message += ": " + error.message();
  return Failure{FailureKind::server, std::move(message), error.code()};
}

}  // namespace tumble::client
