
/* c = a B for a (rows x inner), the factor's entry (k, col) at b[k * bk + col * bc]: b
 * itself (bk = cols, bc = 1) or a transposed one (bk = 1, bc = inner), row-major c. */
static void product(const double *a, const double *b, double *c, int rows, int inner, int cols,
                    int bk, int bc)
{
    for (int r = 0; r < rows; r++) {
        for (int col = 0; col < cols; col++) {
            double s = 0.0;
            for (int k = 0; k < inner; k++) {
                s += a[r * inner + k] * b[k * bk + col * bc];
            }
            c[r * cols + col] = s;
        }
    }
}

/* c = a b for a (rows x inner) and b (inner x cols), row-major. */
static void multiply(const double *a, const double *b, double *c, int rows, int inner, int cols)
{
    product(a, b, c, rows, inner, cols, cols, 1);
}

/* c = a b^T for a (rows x inner) and b (cols x inner), row-major. */
static void multiply_transposed(const double *a, const double *b, double *c, int rows,
                                int inner, int cols)
{
    product(a, b, c, rows, inner, cols, 1, inner);
}

/* out = exp(a) (TC_STATES square) by scaling and squaring of a Taylor polynomial; t1, t2
 * scratch. Returns 0 when a is not finite. */
static int exponential(const double *a, double *out, double *t1, double *t2)
{
    const int n = TC_STATES;
    double norm = 0.0;
    for (int col = 0; col < n; col++) {
        double s = 0.0;
        for (int r = 0; r < n; r++) {
            s += fabs(a[r * n + col]);
        }
        if (!isfinite(s)) {
            return 0;
        }
        norm = fmax(norm, s);
    }
    int halvings = 0;
    double scale = 1.0;
    while (norm > SCALED_NORM && halvings < MAX_HALVINGS) {
        norm *= 0.5;
        scale *= 0.5;
        halvings++;
    }
    for (int i = 0; i < n * n; i++) {
        t1[i] = a[i] * scale;
    }
    for (int r = 0; r < n; r++) {
        for (int col = 0; col < n; col++) {
            const double identity = r == col ? 1.0 : 0.0;
            out[r * n + col] = identity + t1[r * n + col] / (double)TAYLOR_DEGREE;
        }
    }
    for (int k = TAYLOR_DEGREE - 1; k >= 1; k--) {
        multiply(t1, out, t2, n, n, n);
        for (int r = 0; r < n; r++) {
            for (int col = 0; col < n; col++) {
                const double identity = r == col ? 1.0 : 0.0;
                out[r * n + col] = identity + t2[r * n + col] / (double)k;
            }
        }
    }
    for (int h = 0; h < halvings; h++) {
        multiply(out, out, t2, n, n, n);
        for (int i = 0; i < n * n; i++) {
            out[i] = t2[i];
        }
    }
    return 1;
}

/* inverse = s^-1 for a symmetric positive definite s (m x m) through its Cholesky factor l
 * (scratch). Returns 0 when s is not positive definite. */
static int invert_spd(const double *s, int m, double *l, double *inverse)
{
    for (int i = 0; i < m * m; i++) {
        l[i] = 0.0;
    }
    for (int j = 0; j < m; j++) {
        double d = s[j * m + j];
        for (int k = 0; k < j; k++) {
            d -= l[j * m + k] * l[j * m + k];
        }
        if (!(d > 0.0)) {
            return 0;
        }
        l[j * m + j] = sqrt(d);
        for (int i = j + 1; i < m; i++) {
            double v = s[i * m + j];
            for (int k = 0; k < j; k++) {
                v -= l[i * m + k] * l[j * m + k];
            }
            l[i * m + j] = v / l[j * m + j];
        }
    }
    for (int i = 0; i < m * m; i++) {
        inverse[i] = 0.0;
    }
    for (int j = 0; j < m; j++) {
        inverse[j * m + j] = 1.0 / l[j * m + j];
        for (int i = j + 1; i < m; i++) {
            double v = 0.0;
            for (int k = j; k < i; k++) {
                v += l[i * m + k] * inverse[k * m + j];
            }
            inverse[i * m + j] = -v / l[i * m + i];
        }
    }
    for (int i = 0; i < m * m; i++) {
        l[i] = inverse[i];
    }
    for (int r = 0; r < m; r++) {
        for (int c = 0; c < m; c++) {
            double v = 0.0;
            for (int k = r > c ? r : c; k < m; k++) {
                v += l[k * m + r] * l[k * m + c];
            }
            inverse[r * m + c] = v;
        }
    }
    return 1;
}
