// The knitout writer: the canonical text form of a Program.
//
// Canonical form: the magic line `;!knitout-N`, the headers as
// `;;Key: value` in their order, then one line per instruction with single
// spaces between tokens, numbers in their shortest exact decimal form, and a
// trailing comment as ` ;text`. Blank lines are not kept. For every Program p,
// parse(write(p)) == p, and write is idempotent on its own output.
#pragma once

#include <iosfwd>
#include <string>
#include <string_view>

#include "knitout/program.hpp"

namespace knitout {

void write(std::ostream& out, const Program& program);
std::string write_to_string(const Program& program);

// Appends one instruction (no newline). `comment` is written as ` ;comment`
// after the operation (or as `;comment` for a comment-only line); `text` is
// the instruction's side text (unknown extension, x-vis-color colour).
void append_instruction(std::string& out, const CarrierTable& carriers,
                        const Instruction& instruction, std::string_view comment,
                        std::string_view text);

// Shortest decimal text that reads back as exactly `value` ("0.25", "-1"):
// how a knitout number is written, in a program and wherever a message or
// picture quotes one (the VM's, the DAT backend's).
std::string format_number(double value);

}  // namespace knitout
