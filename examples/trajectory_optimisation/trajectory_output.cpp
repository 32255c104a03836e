// trajectory_output.hpp: the table and the gnuplot figure.
#include "trajectory_output.hpp"

#include <cstdio>
#include <cstdlib>

namespace trajopt {

std::vector<Node> nodes_of(const Problem& problem, const std::vector<double>& x) {
  const int N = problem.intervals;
  std::vector<Node> nodes(N + 1);
  for (int k = 0; k <= N; ++k) {
    Node& node = nodes[k];
    node.t = problem.duration * k / N;
    const double* q = x.data() + ShootingNlp::state_index(k);
    const double* tau = x.data() + ShootingNlp::torque_index(k < N ? k : N - 1);
    for (int i = 0; i < kDof; ++i) {
      node.q[i] = q[i];
      node.qd[i] = q[kDof + i];
      node.tau[i] = tau[i];
    }
    hand_height(problem.law, node.q, node.qd, node.height, node.height_rate, node.height_curvature);
    node.nu = dynamics(problem.law, node.q, node.qd, node.tau).nu;
  }
  return nodes;
}

bool write_trajectory(const std::string& out_dir, const std::vector<Node>& nodes) {
  const std::string csv = out_dir + "/trajectory.csv", script = out_dir + "/trajectory.gp";
  FILE* f = std::fopen(csv.c_str(), "w");
  if (!f) {
    std::fprintf(stderr, "trajectory_optimisation: cannot write %s\n", csv.c_str());
    return false;
  }
  std::fprintf(f, "t");
  for (const char* name : {"q", "qd", "tau"})
    for (int i = 1; i <= kDof; ++i) std::fprintf(f, ",%s%d", name, i);
  std::fprintf(f, ",height,height_rate,nu\n");
  for (const Node& n : nodes) {
    std::fprintf(f, "%.17g", n.t);
    for (const double* v : {n.q, n.qd, n.tau})
      for (int i = 0; i < kDof; ++i) std::fprintf(f, ",%.17g", v[i]);
    std::fprintf(f, ",%.17g,%.17g,%.17g\n", n.height, n.height_rate, n.nu);
  }
  std::fclose(f);

  f = std::fopen(script.c_str(), "w");
  if (!f) {
    std::fprintf(stderr, "trajectory_optimisation: cannot write %s\n", script.c_str());
    return false;
  }
  // Columns: 1 t, 2-8 q, 9-15 qd, 16-22 tau, 23 height, 24 height_rate, 25 nu.
  std::fprintf(f,
               "set terminal pngcairo size 900,900 font ',10'\n"
               "set output '%s/trajectory.png'\n"
               "set datafile separator ','\n"
               "set key autotitle columnhead outside right\n"
               "set grid\n"
               "set multiplot layout 3,1 title 'Panda: minimum-effort hand motion on a plane (Ipopt, exact Jacobian)'\n"
               "set ylabel 'joint torque [N m]'\n"
               "plot for [i=16:22] '%s' using 1:i with steps lw 1.5\n"
               "set ylabel 'hand height over the plane [m]'\n"
               "plot '%s' using 1:23 with linespoints pt 7 ps 0.5 title 'height'\n"
               "set ylabel 'plane force nu [N]'\n"
               "set xlabel 't [s]'\n"
               "plot '%s' using 1:25 with linespoints pt 7 ps 0.5 title 'nu'\n"
               "unset multiplot\n",
               out_dir.c_str(), csv.c_str(), csv.c_str(), csv.c_str());
  std::fclose(f);
  const std::string command = "gnuplot '" + script + "'";
  if (std::system(command.c_str()) != 0) {
    std::fprintf(stderr, "trajectory_optimisation: `%s` failed (Debian: gnuplot-nox)\n", command.c_str());
    return false;
  }
  return true;
}

}  // namespace trajopt
