// nearcap/view/viewer_commands.hpp — what the viewer's keys do, by name.
//
// One table serves the window's keys and the scripted key sequences
// (`nearcap view --keys "w w d c wait"`), so that a script drives exactly
// the code a person's key presses drive:
//   w s a d e q         move forward, back, left, right, up, down (one step)
//   left right up down  turn 5 degrees (the arrow keys; a mouse drag turns too)
//   [ ]                 halve, double the step
//   m n                 next, previous method (1 ... 9 pick one directly)
//   l                   next light: every light, then each one alone
//   c                   the crack overlay on or off (the exact reference of
//                       the frame shown, computed in the background)
//   h                   the status line on or off
//   p                   save the view as a scene file (view-NNN.json)
//   escape              quit
//   wait                (scripts only) wait until the crack overlay of the
//                       frame shown is ready
#pragma once

#include <string>
#include <vector>

namespace nearcap::view {

enum class ViewerCommand {
  Forward,
  Back,
  Left,
  Right,
  Up,
  Down,
  TurnLeft,
  TurnRight,
  TurnUp,
  TurnDown,
  SlowerSteps,
  FasterSteps,
  NextMethod,
  PreviousMethod,
  PickMethod,  // with an index (the digit - 1)
  NextLight,
  ToggleCracks,
  ToggleStatusLine,
  SaveView,
  Quit,
  WaitForCracks,
};

struct ViewerInput {
  ViewerCommand command;
  int index = 0;        // PickMethod's method index
  double amount = 1.0;  // moves in steps, turns in 5-degree units (a mouse drag gives fractions)
};

// The command a key name (the table above) stands for; false when none does.
bool command_for_key(const std::string& name, ViewerInput& input);

// A script: key names separated by spaces or commas.  Throws Error(Usage)
// naming the first unknown key and its position.
std::vector<ViewerInput> parse_key_script(const std::string& script);

// The table above as help text (one line per key), for --help and the README.
std::string key_help();

}  // namespace nearcap::view
