// The viewer's keys (see viewer_commands.hpp).
#include "nearcap/view/viewer_commands.hpp"

#include <array>

#include "nearcap/error.hpp"

namespace nearcap::view {
namespace {

struct Key {
  const char* name;
  ViewerCommand command;
};

constexpr std::array<Key, 20> kKeys{{
    {"w", ViewerCommand::Forward},
    {"s", ViewerCommand::Back},
    {"a", ViewerCommand::Left},
    {"d", ViewerCommand::Right},
    {"e", ViewerCommand::Up},
    {"q", ViewerCommand::Down},
    {"left", ViewerCommand::TurnLeft},
    {"right", ViewerCommand::TurnRight},
    {"up", ViewerCommand::TurnUp},
    {"down", ViewerCommand::TurnDown},
    {"[", ViewerCommand::SlowerSteps},
    {"]", ViewerCommand::FasterSteps},
    {"m", ViewerCommand::NextMethod},
    {"n", ViewerCommand::PreviousMethod},
    {"l", ViewerCommand::NextLight},
    {"c", ViewerCommand::ToggleCracks},
    {"h", ViewerCommand::ToggleStatusLine},
    {"p", ViewerCommand::SaveView},
    {"escape", ViewerCommand::Quit},
    {"wait", ViewerCommand::WaitForCracks},
}};

}  // namespace

bool command_for_key(const std::string& name, ViewerInput& input) {
  if (name.size() == 1 && name[0] >= '1' && name[0] <= '9') {
    input = {ViewerCommand::PickMethod, name[0] - '1', 1.0};
    return true;
  }
  for (const Key& k : kKeys)
    if (name == k.name) {
      input = {k.command, 0, 1.0};
      return true;
    }
  return false;
}

std::vector<ViewerInput> parse_key_script(const std::string& script) {
  std::vector<ViewerInput> out;
  std::size_t i = 0, position = 0;
  while (i < script.size()) {
    if (script[i] == ' ' || script[i] == ',' || script[i] == '\t' || script[i] == '\n') {
      ++i;
      continue;
    }
    std::size_t j = i;
    while (j < script.size() && script[j] != ' ' && script[j] != ',' && script[j] != '\t' && script[j] != '\n') ++j;
    const std::string name = script.substr(i, j - i);
    ++position;
    ViewerInput input{};
    if (!command_for_key(name, input))
      throw Error(ErrorKind::Usage, "--keys: key " + std::to_string(position) + " '" + name +
                                        "' is not a viewer key (w s a d e q, left right up down, [ ], m n 1-9, l, c, "
                                        "h, p, escape, wait)");
    out.push_back(input);
    i = j;
  }
  return out;
}

std::string key_help() {
  return "w s a d e q: move forward, back, left, right, up, down (one step); arrows or a mouse drag: turn; "
         "[ ]: halve, double the step; m n: next, previous method (1-9 pick one); l: next light (all, then each); "
         "c: crack overlay against the exact reference (computed in the background); h: status line; "
         "p: save the view as a scene file; escape: quit";
}

}  // namespace nearcap::view
