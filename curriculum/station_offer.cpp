#include "curriculum/station_offer.h"

namespace incise::curriculum {

bool station_fits(const Task& task, std::string_view station_kind) {
  return task.station_kind.empty() || task.station_kind == station_kind;
}

namespace {

// "a bench station", "an arthroscopy station", "an endoscopy station".
std::string a_station(std::string_view kind) {
  const bool vowel = std::string_view("aeiou").find(kind.front()) != std::string_view::npos;
  return (vowel ? "an " : "a ") + std::string(kind) + " station";
}

}  // namespace

std::string station_misfit(const Task& task, std::string_view station_name,
                           std::string_view station_kind) {
  if (station_fits(task, station_kind)) return "";
  const std::string is =
      station_kind.empty() ? "declares no kind" : "is " + a_station(station_kind);
  return "task \"" + task.name + "\" needs " + a_station(task.station_kind) + "; " +
         std::string(station_name) + " " + is;
}

std::vector<TaskOffer> station_offer(const Curriculum& curriculum, std::string_view station_kind,
                                     const std::vector<TaskProgress>* progress) {
  std::vector<TaskOffer> offer;
  for (const Module& module : curriculum.modules) {
    for (const Task& task : module.tasks) {
      if (!station_fits(task, station_kind)) continue;
      TaskOffer o{&task, module.name, ""};
      if (progress != nullptr) {
        if (const TaskProgress* p = find_progress(*progress, task.key))
          o.locked_reason = locked_reason(curriculum, *p);
      }
      offer.push_back(std::move(o));
    }
  }
  return offer;
}

}  // namespace incise::curriculum
