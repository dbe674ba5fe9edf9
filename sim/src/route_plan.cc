// The loop planner: a random walk on the directed edges of the road graph,
// closed by a shortest admissible path (Dijkstra over directed edges, so that
// the closing path never needs a U-turn or a too-sharp turn, including the
// final turn back into the first edge).
#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>
#include <sstream>
#include <utility>
#include <vector>

#include "route_internal.h"

namespace groundline::sim::internal {
namespace {

constexpr double kUnreached = std::numeric_limits<double>::infinity();

struct Directed {
  int from = 0;
  int to = 0;
  int undirected = 0;
  double length_m = 0.0;
  double heading_rad = 0.0;
  double preference = 1.0;
};

struct Transition {
  int next = 0;
  double loss_m = 0.0;  // length saved by smoothing the corner
};

}  // namespace

core::Result<std::vector<int>> PlanLoop(const RoadGraph& roads, const RouteOptions& options,
                                        double tolerance_m, double good_enough_m,
                                        std::mt19937_64* rng) {
  std::vector<Directed> edges;
  for (std::size_t e = 0; e < roads.edges.size(); ++e) {
    const RoadGraph::Edge& edge = roads.edges[e];
    for (const auto& [a, b] : {std::pair(edge.from, edge.to), std::pair(edge.to, edge.from)}) {
      const Vector2 d =
          roads.nodes_m[static_cast<std::size_t>(b)] - roads.nodes_m[static_cast<std::size_t>(a)];
      if (d.norm() <= 0.0) continue;
      edges.push_back(
          {a, b, static_cast<int>(e), d.norm(), std::atan2(d.y(), d.x()), edge.preference});
    }
  }
  if (edges.empty()) return core::Status::Error("route: the world's road graph has no edges");

  // Admissible successors and their smoothing losses; predecessors for Dijkstra.
  std::vector<std::vector<Transition>> succ(edges.size()), pred(edges.size());
  for (std::size_t d = 0; d < edges.size(); ++d) {
    for (std::size_t n = 0; n < edges.size(); ++n) {
      if (edges[n].from != edges[d].to || edges[n].undirected == edges[d].undirected) continue;
      const double angle = std::abs(core::WrapAngle(edges[n].heading_rad - edges[d].heading_rad));
      if (angle > options.max_turn_angle_rad) continue;
      const TurnShape turn = ComputeTurn(angle, options.turn_radius_m, options.transition_length_m);
      const double loss_m = 2.0 * turn.tangent_length_m - turn.curve_length_m;
      succ[d].push_back({static_cast<int>(n), loss_m});
      pred[n].push_back({static_cast<int>(d), loss_m});
    }
  }

  const double target_m = options.length_m;
  std::vector<int> best_nodes;
  double best_error_m = kUnreached;
  double best_length_m = 0.0;
  std::uniform_int_distribution<std::size_t> pick_first(0, edges.size() - 1);
  for (int attempt = 0; attempt < options.max_walk_attempts; ++attempt) {
    const int first = static_cast<int>(pick_first(*rng));
    const int start_node = edges[static_cast<std::size_t>(first)].from;

    // cost[d]: smallest added length from the end of d back into `first`;
    // next[d] is the edge to take (-1: turn straight into `first`).
    std::vector<double> cost(edges.size(), kUnreached);
    std::vector<int> next(edges.size(), -2);
    using Item = std::pair<double, int>;
    std::priority_queue<Item, std::vector<Item>, std::greater<>> queue;
    for (const Transition& t : pred[static_cast<std::size_t>(first)]) {
      if (-t.loss_m < cost[static_cast<std::size_t>(t.next)]) {
        cost[static_cast<std::size_t>(t.next)] = -t.loss_m;
        next[static_cast<std::size_t>(t.next)] = -1;
        queue.push({-t.loss_m, t.next});
      }
    }
    while (!queue.empty()) {
      const auto [c, d] = queue.top();
      queue.pop();
      if (c > cost[static_cast<std::size_t>(d)]) continue;
      for (const Transition& t : pred[static_cast<std::size_t>(d)]) {
        const double candidate = c + edges[static_cast<std::size_t>(d)].length_m - t.loss_m;
        if (candidate < cost[static_cast<std::size_t>(t.next)]) {
          cost[static_cast<std::size_t>(t.next)] = candidate;
          next[static_cast<std::size_t>(t.next)] = d;
          queue.push({candidate, t.next});
        }
      }
    }

    // The walk; remember the prefix whose closed loop is nearest the target.
    std::vector<int> walk = {first};
    std::vector<int> visits(roads.edges.size(), 0);
    ++visits[static_cast<std::size_t>(edges[static_cast<std::size_t>(first)].undirected)];
    double length_m = edges[static_cast<std::size_t>(first)].length_m;
    std::size_t best_prefix = 0;
    double prefix_error_m = kUnreached;
    double prefix_length_m = 0.0;
    while (true) {
      const std::size_t cur = static_cast<std::size_t>(walk.back());
      if (cost[cur] < kUnreached && std::abs(length_m + cost[cur] - target_m) < prefix_error_m) {
        prefix_error_m = std::abs(length_m + cost[cur] - target_m);
        prefix_length_m = length_m + cost[cur];
        best_prefix = walk.size();
      }
      if (length_m > target_m) break;
      std::vector<double> weights;
      std::vector<const Transition*> options_here;
      for (const Transition& t : succ[cur]) {
        if (cost[static_cast<std::size_t>(t.next)] == kUnreached) continue;
        const Directed& e = edges[static_cast<std::size_t>(t.next)];
        const double used = visits[static_cast<std::size_t>(e.undirected)];
        weights.push_back(e.preference / ((1.0 + used) * (1.0 + used)));
        options_here.push_back(&t);
      }
      if (options_here.empty()) break;
      std::discrete_distribution<std::size_t> choose(weights.begin(), weights.end());
      const Transition& t = *options_here[choose(*rng)];
      const Directed& e = edges[static_cast<std::size_t>(t.next)];
      length_m += e.length_m - t.loss_m;
      ++visits[static_cast<std::size_t>(e.undirected)];
      walk.push_back(t.next);
    }
    if (best_prefix == 0 || prefix_error_m >= best_error_m) continue;
    walk.resize(best_prefix);
    while (next[static_cast<std::size_t>(walk.back())] >= 0) {
      walk.push_back(next[static_cast<std::size_t>(walk.back())]);
    }
    best_nodes = {start_node};
    for (int d : walk) best_nodes.push_back(edges[static_cast<std::size_t>(d)].to);
    best_error_m = prefix_error_m;
    best_length_m = prefix_length_m;
    if (best_error_m <= good_enough_m) break;
  }
  if (best_nodes.empty()) {
    return core::Status::Error(
        "route: the road graph has no closed loop without U-turns or turns sharper than "
        "max_turn_angle_rad");
  }
  if (best_error_m > tolerance_m) {
    std::ostringstream message;
    message << "route: the nearest closed loop found is " << best_length_m
            << " m long for a requested length_m of " << target_m
            << " m; change length_m, raise length_tolerance_fraction or drive an open route "
               "(closed_loop: false), which has exactly length_m";
    return core::Status::Error(message.str());
  }
  return best_nodes;
}

}  // namespace groundline::sim::internal
