#pragma once
// One function per `gather` subcommand; each returns the process exit status.
namespace gather {
namespace cmd {

int info(int argc, char** argv);  // gather info SCENARIO

}  // namespace cmd
}  // namespace gather
