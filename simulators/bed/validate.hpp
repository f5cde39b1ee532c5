// bed::validate: the judge of knitout programs.
//
// validate = parse + run every instruction through bed::Machine. Everything
// wrong goes to one DiagnosticSink: the parser's K codes and the machine's V
// codes (docs/diagnostics.md), each at its source line. A program is valid
// for a machine when the sink holds no errors afterwards; warnings are
// findings a careful operator wants to see but that do not stop a machine.
//
// Callers that emit knitout (the planner, backends' tests) pass their
// Program to `validate` and expect `sink.has_errors() == false`.
#pragma once

#include <iosfwd>
#include <string>
#include <string_view>

#include "knitout/diagnostic.hpp"
#include "knitout/program.hpp"
#include "simulators/bed/machine.hpp"
#include "simulators/bed/profile.hpp"
#include "simulators/bed/stats.hpp"

namespace bed {

// Runs a parsed Program (its parse diagnostics are the caller's: they went
// to the sink given to knitout::parse). `source` names it in diagnostics.
Stats validate(const knitout::Program& program, const MachineProfile& profile,
               knitout::DiagnosticSink& sink, std::string_view source = "<program>",
               MachineOptions options = {});

// Streams `in` through knitout::Reader and the machine, one instruction at a
// time: memory does not grow with the length of the input (unless an
// Observer keeps things). Parse and machine diagnostics both go to `sink`.
Stats validate_stream(std::istream& in, std::string_view source, const MachineProfile& profile,
                      knitout::DiagnosticSink& sink, MachineOptions options = {});

// validate_stream on a file; a file that cannot be opened is a K090 error.
Stats validate_file(const std::string& path, const MachineProfile& profile,
                    knitout::DiagnosticSink& sink, MachineOptions options = {});

}  // namespace bed
