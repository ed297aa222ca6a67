"""An independent port of lockstep's Q16.16 arithmetic, in Python.

Written from the rules in vectors/README.md and docs/SPEC.md 0.3 only (not
translated from the C++), with Python's exact integers: a value is its raw
int32 R (x = R / 2^16); every operation that drops bits rounds to nearest,
ties to even (_rdiv and _rsqrt below, from Python's exact floor division);
results outside int32 are clamped
and raise "overflow". Every function returns (result, status) where status is
the set of flag names raised. Standard library only.

vectors/python/verify_vectors.py runs it against vectors/data/arithmetic.json.
"""

import math
import struct

INT32_MAX = 2**31 - 1
INT32_MIN = -(2**31)
ONE = 1 << 16

# Status flag names in bit order (bit 0 first), as in the vector files.
FLAG_ORDER = ("overflow", "div_by_zero", "sqrt_negative", "normalize_zero", "invalid")


def _rdiv(n, d):
    """round(n / d) to nearest, ties to even, exactly (d != 0)."""
    if d < 0:
        n, d = -n, -d
    q, r = divmod(n, d)  # floor, 0 <= r < d
    if 2 * r > d or (2 * r == d and q % 2 == 1):
        q += 1
    return q


def _r16(n):
    """round(n / 2^16) to nearest, ties to even."""
    return _rdiv(n, ONE)


def _rsqrt(n):
    """round(sqrt(n)) to nearest (never a tie for an integer n >= 0)."""
    r = math.isqrt(n)
    return r + 1 if 4 * n > (2 * r + 1) ** 2 else r


def _clamp(v, st):
    """Clamp an exact integer into int32, raising overflow when it clamps."""
    if v > INT32_MAX:
        st.add("overflow")
        return INT32_MAX
    if v < INT32_MIN:
        st.add("overflow")
        return INT32_MIN
    return v


# --- scalars ---------------------------------------------------------------

def from_int(i, st):
    if i > 32767 or i < -32768:
        st.add("overflow")
        return INT32_MAX if i > 0 else INT32_MIN
    return i * ONE


def from_double_bits(hex16, st):
    """eq 22: round(x * 2^16) to nearest, ties to even; x given as its IEEE bits."""
    x = struct.unpack(">d", bytes.fromhex(hex16))[0]
    if math.isnan(x):
        st.add("invalid")
        return 0
    scaled = x * 65536.0  # exact: a power-of-two scale (or +-inf)
    if scaled >= 2147483647.5 or scaled < -2147483648.5:
        # beyond the int32 range even after rounding (2147483647.5 ties to the even 2^31)
        st.add("overflow")
        return INT32_MAX if scaled > 0 else INT32_MIN
    return _clamp(round(scaled), st)  # Python's round() on a float: exact, ties to even


def add(a, b, st):
    return _clamp(a + b, st)


def sub(a, b, st):
    return _clamp(a - b, st)


def neg(a, st):
    return _clamp(-a, st)


def mul(a, b, st):
    return _clamp(_r16(a * b), st)


def div(a, b, st):
    if b == 0:
        st.add("div_by_zero")
        return INT32_MAX if a >= 0 else INT32_MIN
    return _clamp(_rdiv(a << 16, b), st)


def reciprocal(a, st):
    return div(ONE, a, st)


def sqrt(a, st):
    if a < 0:
        st.add("sqrt_negative")
        return 0
    return _rsqrt(a << 16)


def q_abs(a, st):
    return _clamp(abs(a), st)


def q_min(a, b, st):
    return min(a, b)


def q_max(a, b, st):
    return max(a, b)


def floor_to_int(a, st):
    return a >> 16


# --- vectors, quaternions, matrices: exact sums, one rounding to nearest --------------------

def dot(a, b, st):
    return _clamp(_r16(sum(x * y for x, y in zip(a, b))), st)


def cross(a, b, st):
    return [_clamp(_r16(a[1] * b[2] - a[2] * b[1]), st),
            _clamp(_r16(a[2] * b[0] - a[0] * b[2]), st),
            _clamp(_r16(a[0] * b[1] - a[1] * b[0]), st)]


def length_sq(a, st):
    return _clamp(_r16(sum(x * x for x in a)), st)


def length(a, st):
    return _clamp(_rsqrt(sum(x * x for x in a)), st)


def normalize(a, st):
    n = _rsqrt(sum(x * x for x in a))
    if n == 0:
        st.add("normalize_zero")
        return [0, 0, 0]
    return [_clamp(_rdiv(x << 16, n), st) for x in a]


def quat_mul(a, b, st):
    aw, ax, ay, az = a
    bw, bx, by, bz = b
    return [_clamp(_r16(aw * bw - ax * bx - ay * by - az * bz), st),
            _clamp(_r16(aw * bx + ax * bw + ay * bz - az * by), st),
            _clamp(_r16(aw * by - ax * bz + ay * bw + az * bx), st),
            _clamp(_r16(aw * bz + ax * by - ay * bx + az * bw), st)]


def quat_length_sq(q, st):
    return _clamp(_r16(sum(x * x for x in q)), st)


def quat_normalize(q, st):
    c = [-INT32_MAX if x == INT32_MIN else x for x in q]
    n = _rsqrt(sum(x * x for x in c))
    if n == 0:
        st.add("normalize_zero")
        return [ONE, 0, 0, 0]
    return [_clamp(_rdiv(x << 16, n), st) for x in c]


def rotation_matrix(q, st):
    w, x, y, z = q

    def diag(a, b):  # 1 - 2(a^2 + b^2)
        return _clamp(_r16((1 << 32) - 2 * a * a - 2 * b * b), st)

    def off(a, b, c, d, sign):  # 2(ab +- cd)
        return _clamp(_r16(2 * a * b + sign * 2 * c * d), st)

    return [[diag(y, z), off(x, y, w, z, -1), off(x, z, w, y, +1)],
            [off(x, y, w, z, +1), diag(x, z), off(y, z, w, x, -1)],
            [off(x, z, w, y, -1), off(y, z, w, x, +1), diag(x, y)]]


def mat_mul_vec(m, v, st):
    return [dot(row, v, st) for row in m]


def mat_transpose_mul_vec(m, v, st):
    return [_clamp(_r16(sum(m[j][i] * v[j] for j in range(3))), st) for i in range(3)]


def rotate(q, v, st):
    return mat_mul_vec(rotation_matrix(q, st), v, st)


# The operations of arithmetic.json by name: (function, names of its inputs).
OPERATIONS = {
    "from_int": (from_int, ("i",)),
    "from_double": (from_double_bits, ("x",)),
    "add": (add, ("a", "b")),
    "sub": (sub, ("a", "b")),
    "neg": (neg, ("a",)),
    "mul": (mul, ("a", "b")),
    "div": (div, ("a", "b")),
    "reciprocal": (reciprocal, ("a",)),
    "sqrt": (sqrt, ("a",)),
    "abs": (q_abs, ("a",)),
    "min": (q_min, ("a", "b")),
    "max": (q_max, ("a", "b")),
    "floor_to_int": (floor_to_int, ("a",)),
    "dot": (dot, ("a", "b")),
    "cross": (cross, ("a", "b")),
    "length_sq": (length_sq, ("a",)),
    "length": (length, ("a",)),
    "normalize": (normalize, ("a",)),
    "quat_mul": (quat_mul, ("a", "b")),
    "quat_length_sq": (quat_length_sq, ("a",)),
    "quat_normalize": (quat_normalize, ("a",)),
    "rotation_matrix": (rotation_matrix, ("a",)),
    "mat_mul_vec": (mat_mul_vec, ("m", "v")),
    "mat_transpose_mul_vec": (mat_transpose_mul_vec, ("m", "v")),
    "rotate": (rotate, ("q", "v")),
}


def compute(operation, inputs):
    """Runs one operation: returns (result, status list in bit order)."""
    fn, names = OPERATIONS[operation]
    st = set()
    r = fn(*[inputs[n] for n in names], st)
    return r, [f for f in FLAG_ORDER if f in st]


# --- the state hash (eq 92) -------------------------------------------------

FNV_OFFSET = 0xCBF29CE484222325
FNV_PRIME = 0x100000001B3


def state_hash(bodies):
    """FNV-1a 64 over each body's 13 raw int32 (p, q, v, w) as 4 little-endian
    bytes each, then one byte asleep. bodies: rows [13 raw..., asleep, ...]."""
    h = FNV_OFFSET
    for b in bodies:
        data = struct.pack("<13i", *b[:13]) + bytes([1 if b[13] else 0])
        for byte in data:
            h = ((h ^ byte) * FNV_PRIME) & 0xFFFFFFFFFFFFFFFF
    return "%016x" % h
