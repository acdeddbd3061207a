#include "devices/agent/force_model_evaluator.h"

#include <cmath>

namespace incise::devices::agent {

void ForceModelEvaluator::set_model(const ForceModel& model, Clock::time_point received_at) {
  model_ = model;
  received_at_ = received_at;
  has_model_ = true;
}

bool ForceModelEvaluator::fresh(Clock::time_point now) const {
  return has_model_ && now - received_at_ <= kModelMaxGap;
}

Vec3 ForceModelEvaluator::force_at(const Vec3& position) const {
  if (!has_model_) return {};
  const Vec3& x0 = model_.reference_position;
  const double d[3] = {position.x - x0.x, position.y - x0.y, position.z - x0.z};
  const auto& k = model_.stiffness;
  Vec3 f = model_.force;
  f.x -= k[0] * d[0] + k[1] * d[1] + k[2] * d[2];
  f.y -= k[3] * d[0] + k[4] * d[1] + k[5] * d[2];
  f.z -= k[6] * d[0] + k[7] * d[1] + k[8] * d[2];
  const double magnitude = std::sqrt(f.x * f.x + f.y * f.y + f.z * f.z);
  if (magnitude > kMaxModelForce) {
    const double scale = kMaxModelForce / magnitude;
    f = {f.x * scale, f.y * scale, f.z * scale};
  }
  return f;
}

}  // namespace incise::devices::agent
