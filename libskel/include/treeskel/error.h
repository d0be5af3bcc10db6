/// @file error.h
/// Exceptions thrown by treeskel and the precondition macro used to raise them.
#pragma once

#include <stdexcept>
#include <string>

namespace treeskel {

/// Base of every error treeskel throws. `what()` is a complete sentence meant for the user.
class Error : public std::runtime_error {
public:
  using std::runtime_error::runtime_error;
};

/// The input (a file, a cloud, a skeleton) cannot be used; the message says why and where.
class InputError : public Error {
public:
  using Error::Error;
};

/// An option has a value the method cannot work with.
class OptionError : public Error {
public:
  using Error::Error;
};

namespace detail {
[[noreturn]] void fail_precondition(const char* file, int line, const std::string& message);
}  // namespace detail

}  // namespace treeskel

/// Throws treeskel::Error with file:line when `cond` is false. For internal invariants and API misuse;
/// bad user data is reported with InputError and a message that names the data.
#define TREESKEL_REQUIRE(cond, message)                                         \
  do {                                                                          \
    if (!(cond)) ::treeskel::detail::fail_precondition(__FILE__, __LINE__, message); \
  } while (false)
