// through_matrix's first case, a block of rotations in vector lanes: basis_of and rotation_of's
// operations (walk.hpp), each the same IEEE one in the same order, so that every lane's bits are the
// scalar's. Its own file, compiled without errno (CMakeLists.txt): sqrt is then a vector instruction,
// not a call kept for the errno of a negative argument (the argument is over 1 in every lane kept).
#include "walk.hpp"

namespace tfcore {

TFCORE_VECTOR_VERSIONS void turn_positive_traces(double* x, double* y, double* z, double* w, uint8_t* fast, int64_t n) {
    for (int64_t i = 0; i < n; ++i) {
        const double qx = x[i], qy = y[i], qz = z[i], qw = w[i];
        const double s = 2.0 / (qx * qx + qy * qy + qz * qz + qw * qw);
        const double xs = qx * s, ys = qy * s, zs = qz * s;
        const double wx = qw * xs, wy = qw * ys, wz = qw * zs;
        const double xx = qx * xs, xy = qx * ys, xz = qx * zs;
        const double yy = qy * ys, yz = qy * zs, zz = qz * zs;
        const double m00 = 1.0 - (yy + zz), m01 = xy - wz, m02 = xz + wy;
        const double m10 = xy + wz, m11 = 1.0 - (xx + zz), m12 = yz - wx;
        const double m20 = xz - wy, m21 = yz + wx, m22 = 1.0 - (xx + yy);
        const double trace = m00 + m11 + m22;
        fast[i] = trace > 0.0;
        double r = std::sqrt(trace + 1.0);
        w[i] = r * 0.5;
        r = 0.5 / r;
        x[i] = (m21 - m12) * r;
        y[i] = (m02 - m20) * r;
        z[i] = (m10 - m01) * r;
    }
}

}  // namespace tfcore
