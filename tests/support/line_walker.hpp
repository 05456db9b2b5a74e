#pragma once
// A small continuous environment for the continuous protocol's tests: a walker
// on a line, observation (x, 2 x), actions left / right by 1 with uniform noise
// of +-0.1. A walk starts at x ~ U(3, 9.5), a test at x = 0 (noiseless). Reaching
// x >= 10 is terminal with reward 1 (the goal); x < -3 is a stop (a bump) that
// puts the walker back at -3, reward -1. The trace is x.

#include <memory>
#include <span>
#include <vector>

#include "engine/tasks/continuous_protocol.hpp"
#include "kernels/random_stream.hpp"

namespace ggk::test_support {

class LineWalker final : public engine::ContinuousEpisode {
 public:
  void start_walk(kernels::RandomStream& random, std::span<double> observation) override {
    x_ = random.uniform(3.0, 9.5);
    observe(observation);
  }
  void start_test(kernels::RandomStream&, std::span<double> observation) override {
    x_ = 0.0;
    observe(observation);
  }
  engine::ContinuousStep step(std::int32_t action, kernels::RandomStream& random,
                              std::span<double> observation) override {
    x_ += (action == 0 ? -1.0 : 1.0) + random.uniform(-0.1, 0.1);
    engine::ContinuousStep step;
    if (x_ >= 10.0) {
      step.reward = 1.0;
      step.terminal = true;
    } else if (x_ < -3.0) {
      x_ = -3.0;
      step.reward = -1.0;
      step.stop = true;
    }
    observe(observation);
    return step;
  }
  void trace(std::vector<double>& out) const override { out.push_back(x_); }

 private:
  void observe(std::span<double> observation) const {
    observation[0] = x_;
    observation[1] = 2.0 * x_;
  }
  double x_ = 0.0;
};

inline engine::ContinuousEnvironment line_walker_environment() {
  engine::ContinuousEnvironment env;
  env.observation_dimension = 2;
  env.num_actions = 2;
  env.action_names = {"left", "right"};
  env.new_episode = [] { return std::make_unique<LineWalker>(); };
  env.trace_dimension = 1;
  env.ended_metric = "success_rate";
  env.stop_flags_array = "samples/bumps";
  return env;
}

inline engine::ContinuousProtocol line_walker_protocol() {
  engine::ContinuousProtocol protocol;
  protocol.series = 10;
  protocol.steps_per_series = 12;
  protocol.test_episodes = 3;
  protocol.test_max_steps = 30;
  protocol.som.rows = 3;
  protocol.som.cols = 4;
  protocol.som.epochs = 10;
  protocol.scale = {10.0, 20.0};
  return protocol;
}

}  // namespace ggk::test_support
