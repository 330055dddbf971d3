// The explicit instantiations that eigen_instances.hpp declares (see there for why), in three
// files so that a parallel build compiles them side by side (together they took 60-70 s).
#include "common/eigen_instances.hpp"

template class Eigen::BDCSVD<Eigen::MatrixXd>;
template class Eigen::JacobiSVD<Eigen::MatrixXd>;
