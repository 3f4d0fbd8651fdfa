/* The rows of a CSV table: every number as Python's `"%.17g" % x` writes it (17 significant
 * digits, correctly rounded, ties to even; "nan", "inf", "-inf", "-0"), so that the text parses
 * back to the same double and is byte for byte the text of csv_text.py's Python path.
 *
 * Fast path: |x| in about [1e-11, 1e44) is x / 10^k rounded to a 17-digit integer in exact
 * 128-bit arithmetic (x = m 2^e, 5^k fits in 64 bits). Anything else (tiny, huge, subnormal)
 * goes to snprintf, whose "%.17g" is correctly rounded too. Built by csv_text.py.
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef unsigned __int128 u128;

#define DIGITS 17
#define MAX_POW5 27                     /* 5^27 < 2^63 */

/* 5^0 .. 5^27 */
static const uint64_t pow5[MAX_POW5 + 1] = {
    1ULL, 5ULL, 25ULL, 125ULL, 625ULL, 3125ULL, 15625ULL, 78125ULL, 390625ULL, 1953125ULL,
    9765625ULL, 48828125ULL, 244140625ULL, 1220703125ULL, 6103515625ULL, 30517578125ULL,
    152587890625ULL, 762939453125ULL, 3814697265625ULL, 19073486328125ULL, 95367431640625ULL,
    476837158203125ULL, 2384185791015625ULL, 11920928955078125ULL, 59604644775390625ULL,
    298023223876953125ULL, 1490116119384765625ULL, 7450580596923828125ULL
};

/* num / den, truncated, and whether rounding to nearest (ties to even) adds one. */
static u128 divide(u128 num, u128 den, int *up) {
    u128 q = num / den, twice = (num % den) << 1;
    *up = twice > den || (twice == den && (q & 1));
    return q;
}

/* m 2^e / 10^k truncated into *d, and in *up whether rounding adds one; 0 where it leaves
 * 128-bit arithmetic (the caller falls back). */
static int scaled(uint64_t m, int e, int k, uint64_t *d, int *up) {
    u128 q;
    if (k >= 0) {                               /* m 2^(e-k) / 5^k */
        int s = e - k;
        if (k > MAX_POW5 || s > 74 || s < -63) return 0;
        q = s >= 0 ? divide((u128)m << s, pow5[k], up) : divide(m, (u128)pow5[k] << -s, up);
    } else {                                    /* m 5^j 2^(e+j) */
        int j = -k, s = e - k;
        if (j > MAX_POW5 || s >= 64 || s <= -127) return 0;
        u128 p = (u128)m * pow5[j];
        if (s >= 0) {
            if (p >> (127 - s)) return 0;
            q = p << s;
            *up = 0;
        } else {
            u128 half = (u128)1 << (-s - 1), rest = p & ((half << 1) - 1);
            q = p >> -s;
            *up = rest > half || (rest == half && (q & 1));
        }
    }
    if (q >> 64) return 0;
    *d = (uint64_t)q;
    return 1;
}

static const char PAIRS[201] =
    "00010203040506070809101112131415161718192021222324252627282930313233343536373839"
    "40414243444546474849505152535455565758596061626364656667686970717273747576777879"
    "8081828384858687888990919293949596979899";

/* v < 10^8 as eight digits (leading zeros kept), two at a time. */
static void eight_digits(char *out, uint32_t v) {
    uint32_t upper = v / 10000, lower = v % 10000;
    memcpy(out, PAIRS + 2 * (upper / 100), 2);
    memcpy(out + 2, PAIRS + 2 * (upper % 100), 2);
    memcpy(out + 4, PAIRS + 2 * (lower / 100), 2);
    memcpy(out + 6, PAIRS + 2 * (lower % 100), 2);
}

/* The 17 digits of a finite x > 0 and its decimal exponent; 0 if the fast path cannot. */
static int digits_of(double x, char *digits, int *exponent) {
    uint64_t bits;
    memcpy(&bits, &x, sizeof bits);
    int biased = (int)(bits >> 52);
    if (biased == 0) return 0;                  /* subnormal: far below the fast range */
    uint64_t m = (bits & ((1ULL << 52) - 1)) | (1ULL << 52), d = 0;
    int e = biased - 1075, up = 0;
    /* floor(log10(x)) guessed from log2(x) in 1/2^20 steps (the mantissa's fraction taken as
     * linear, 78913 / 2^18 for log10(2)): right or off by one, which the loop corrects */
    int64_t log2_fixed = (int64_t)(e + 52) * (1 << 20) + (int64_t)((m - (1ULL << 52)) >> 32);
    int point = (int)((log2_fixed * 78913) >> 38);
    const uint64_t low = 10000000000000000ULL, high = 100000000000000000ULL;
    for (int tries = 0; ; tries++) {           /* correct the guess against exact arithmetic */
        if (tries == 3 || !scaled(m, e, point - (DIGITS - 1), &d, &up)) return 0;
        if (d >= high) point++;                 /* 10^point <= x < 10^(point+1) exactly */
        else if (d < low) point--;
        else break;
    }
    d += up;
    if (d == high) {                            /* rounded up to the next power of ten */
        d = low;
        point++;
    }
    uint64_t tail = d % 10000000000000000ULL;
    digits[0] = (char)('0' + d / 10000000000000000ULL);
    eight_digits(digits + 1, (uint32_t)(tail / 100000000));
    eight_digits(digits + 9, (uint32_t)(tail % 100000000));
    *exponent = point;
    return 1;
}

/* "%.17g" of the digits: trailing zeros dropped, exponent form below 1e-4 and from 1e17. */
static char *g_format(char *out, const char *digits, int point) {
    int used = DIGITS;
    while (used > 1 && digits[used - 1] == '0') used--;
    if (point < -4 || point >= DIGITS) {
        *out++ = digits[0];
        if (used > 1) {
            *out++ = '.';
            memcpy(out, digits + 1, used - 1);
            out += used - 1;
        }
        int shown = point < 0 ? -point : point;
        *out++ = 'e';
        *out++ = point < 0 ? '-' : '+';
        if (shown >= 100) *out++ = (char)('0' + shown / 100);
        *out++ = (char)('0' + shown / 10 % 10);
        *out++ = (char)('0' + shown % 10);
    } else if (point >= 0) {
        memcpy(out, digits, point + 1);
        out += point + 1;
        if (used > point + 1) {
            *out++ = '.';
            memcpy(out, digits + point + 1, used - point - 1);
            out += used - point - 1;
        }
    } else {
        *out++ = '0';
        *out++ = '.';
        for (int i = -1; i > point; i--) *out++ = '0';
        memcpy(out, digits, used);
        out += used;
    }
    return out;
}

/* One number's text at `out`; returns the end. At most 24 characters. */
static char *format_number(char *out, double x) {
    char digits[DIGITS];
    int point;
    if (isnan(x)) {
        memcpy(out, "nan", 3);
        return out + 3;
    }
    if (signbit(x)) {
        *out++ = '-';
        x = -x;
    }
    if (isinf(x)) {
        memcpy(out, "inf", 3);
        return out + 3;
    }
    if (x == 0) {
        *out++ = '0';
        return out;
    }
    if (digits_of(x, digits, &point)) return g_format(out, digits, point);
    return out + snprintf(out, 32, "%.17g", x);
}

/* The last value of a distinct column and its text. */
struct slot {
    uint64_t bits;
    int length;                                 /* 0: nothing formatted yet */
    char text[32];
};

/* The rows of a table into `out`: field j is distinct[fields[j]], or its negation where
 * fields[j] < 0 (distinct[~fields[j]]; never a column holding NaN), each distinct column
 * `rows` doubles long; fields joined by ',', each row ended by '\n'. A value equal to the one
 * above it keeps its text. `out` holds rows * count * 32 bytes. Returns the length written, or
 * (size_t)-1 when memory runs out. */
size_t dyadc_csv_rows(const double *const *distinct, int64_t distinct_count, int64_t rows,
                      const int64_t *fields, int64_t count, char *out) {
    struct slot *slots = calloc(distinct_count ? (size_t)distinct_count : 1, sizeof *slots);
    if (!slots) return (size_t)-1;
    char *start = out;
    for (int64_t i = 0; i < rows; i++) {
        for (int64_t u = 0; u < distinct_count; u++) {
            uint64_t bits;
            memcpy(&bits, &distinct[u][i], sizeof bits);
            if (slots[u].length && slots[u].bits == bits) continue;
            slots[u].bits = bits;
            slots[u].length = (int)(format_number(slots[u].text, distinct[u][i]) - slots[u].text);
        }
        for (int64_t j = 0; j < count; j++) {
            const struct slot *field = &slots[fields[j] < 0 ? ~fields[j] : fields[j]];
            const char *text = field->text;
            int length = field->length;
            if (fields[j] < 0) {                /* "%.17g" of -x: that of x with its sign turned */
                if (*text == '-') {
                    text++;
                    length--;
                } else {
                    *out++ = '-';
                }
            }
            memcpy(out, text, (size_t)length);
            out += length;
            *out++ = j + 1 < count ? ',' : '\n';
        }
    }
    free(slots);
    return (size_t)(out - start);
}
