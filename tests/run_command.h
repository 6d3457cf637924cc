// Test helper: runs a stage program (or any shell command) and gives its exit status.
//
//   run_command(command)   runs `command` with /bin/sh (redirections and environment assignments
//                          included) and returns its exit status: 0 on success, the stage's code
//                          otherwise; a program killed by a signal gives 128 + the signal as dash
//                          reports it (a shell that execs the command instead gives -1: the
//                          signal reaches std::system), and -1 when the shell itself could not run.
//                          Either way a crash is non-zero.
#pragma once

#include <sys/wait.h>

#include <cstdlib>
#include <string>

inline int run_command(const std::string& command) {
  const int status = std::system(command.c_str());
  return status != -1 && WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}
