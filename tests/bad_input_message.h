// Test helper: what a call says about bad input (or about another kind of error).
//
//   std::string bad_input_message(F&& call)
//   std::string bad_input_message(F&& call, const std::string& path)
//   std::string error_message(pipeline::ErrorKind kind, F&& call)
//
// Input:  call, anything callable with no arguments (a lambda around the function under test);
//         path, the file the message must name first ("path: ...").
// Output: the message of the pipeline::Error the call throws; with `path`, the message after
//         "path: ". "no error" when the call returns.
//   An error of another kind than bad_input (error_message: than `kind`), or a message that does not
//   start with "path: ", is a test failure (the message is still returned, so the caller's
//   comparison shows it too).
#pragma once

#include <gtest/gtest.h>

#include <string>

#include "pipeline/error.h"

template <class F>
std::string error_message(pipeline::ErrorKind kind, F&& call) {
  try {
    call();
  } catch (const pipeline::Error& e) {
    EXPECT_EQ(e.kind, kind) << e.what();
    return e.what();
  }
  return "no error";
}

template <class F>
std::string bad_input_message(F&& call) {
  return error_message(pipeline::ErrorKind::bad_input, call);
}

template <class F>
std::string bad_input_message(F&& call, const std::string& path) {
  const std::string message = bad_input_message(call);
  if (message == "no error") return message;
  const std::string named = path + ": ";
  if (message.rfind(named, 0) != 0) {
    ADD_FAILURE() << "the message does not start with \"" << named << "\": " << message;
    return message;
  }
  return message.substr(named.size());
}
