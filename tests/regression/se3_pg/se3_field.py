"""The SE(3) pose field of an se3_pg result (methods/se3_petrov_galerkin.md eq. 36), in NumPy:
H(xi) = H_e Exp_SE3(t Log_SE3(H_e^-1 H_e+1)) on element e, from the nodal positions and
directors of the result file (the K basis is (d3, d1, d2), docs/theory/se3_pg.md), and the
error measures of eqs. (52)-(53)."""
import numpy as np


def hat(w):
    return np.array([[0.0, -w[2], w[1]], [w[2], 0.0, -w[0]], [-w[1], w[0], 0.0]])


def exp_so3(psi):
    x = np.linalg.norm(psi)
    w = hat(psi)
    if x < 1e-8:
        return np.eye(3) + w + 0.5 * w @ w
    return np.eye(3) + np.sin(x) / x * w + (1 - np.cos(x)) / x**2 * w @ w


def log_so3(a):
    c = np.clip((np.trace(a) - 1) / 2, -1.0, 1.0)
    x = np.arccos(c)
    v = np.array([a[2, 1] - a[1, 2], a[0, 2] - a[2, 0], a[1, 0] - a[0, 1]])
    if x < 1e-8:
        return 0.5 * v
    if np.pi - x < 1e-6:
        # Near pi: the axis from the symmetric part.
        s = (a + np.eye(3)) / 2
        k = np.argmax(np.diag(s))
        axis = s[:, k] / np.sqrt(s[k, k])
        if axis @ v < 0:
            axis = -axis
        return x * axis
    return x / (2 * np.sin(x)) * v


def tangent_so3(psi):
    """T(psi) = 1 - ((1 - cos x)/x^2) psi~ + ((x - sin x)/x^3) psi~^2 (methods eq. 78)."""
    x = np.linalg.norm(psi)
    w = hat(psi)
    if x < 1e-8:
        return np.eye(3) - 0.5 * w
    return np.eye(3) - (1 - np.cos(x)) / x**2 * w + (x - np.sin(x)) / x**3 * w @ w


def exp_se3(theta):
    return exp_so3(theta[3:]), tangent_so3(theta[3:]).T @ theta[:3]


def log_se3(a, r):
    psi = log_so3(a)
    return np.concatenate([np.linalg.solve(tangent_so3(psi).T, r), psi])


def frames(directors):
    """A = [d3, d1, d2] per node from directors[node, i, :] = d_(i+1)."""
    return np.stack([directors[:, 2, :], directors[:, 0, :], directors[:, 1, :]], axis=2)


def field(positions, directors, xi):
    """Positions (k, 3) and rotations (k, 3, 3) of the SE(3) field at the global parameters xi
    in [0, 1] (elements equally spaced in xi, methods §5.1)."""
    a = frames(directors)
    n_el = positions.shape[0] - 1
    rs, As = [], []
    for x in xi:
        e = min(int(x * n_el), n_el - 1)
        t = x * n_el - e
        a_rel = a[e].T @ a[e + 1]
        r_rel = a[e].T @ (positions[e + 1] - positions[e])
        theta = log_se3(a_rel, r_rel)
        a_t, r_t = exp_se3(t * theta)
        As.append(a[e] @ a_t)
        rs.append(positions[e] + a[e] @ r_t)
    return np.array(rs), np.array(As)


def errors(positions, directors, ref_positions, ref_directors, k=100):
    """e_r^k of eq. (52) and e_psi^k of eq. (53) WITHOUT its 1/k (methods §13 item 7)."""
    xi = np.arange(k) / (k - 1)
    r, a = field(positions, directors, xi)
    r0, a0 = field(ref_positions, ref_directors, xi)
    e_r = np.sqrt(np.sum(np.linalg.norm(r - r0, axis=1)**2)) / k
    e_psi = np.sqrt(sum(np.linalg.norm(log_so3(a[i].T @ a0[i]))**2 for i in range(k)))
    return e_r, e_psi
