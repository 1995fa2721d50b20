//! The common data row read fast: ASCII cells of plain decimals (`-0.012345`, `17`, no
//! exponent). Such a number with a mantissa m below 2⁵³ and at most 22 digits after the point
//! is m/10ᵏ with m and 10ᵏ both exact doubles, so one IEEE division gives the correctly
//! rounded value (Clinger's fast path): the same double `str::parse` gives. Any other row (an
//! exponent, NaN, an empty cell, a wrong width, non-ASCII text, a comment) is left to the
//! general reader, which also words every error.

/// 10ᵏ for k ≤ 22: every one an exact double.
const POWERS: [f64; 23] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16,
    1e17, 1e18, 1e19, 1e20, 1e21, 1e22,
];

/// 10ᵏ for k ≤ 8, as integers.
const POWERS_U64: [u64; 9] = [
    1,
    10,
    100,
    1_000,
    10_000,
    100_000,
    1_000_000,
    10_000_000,
    100_000_000,
];

/// How many of the eight bytes lead as ASCII digits, and their value (SWAR: one word, no
/// branch per byte). Each byte x = b ⊕ '0' is a digit's value exactly when x ≤ 9; the lowest
/// byte with x + 0x76 or x at 0x80 or above is the first non-digit (a carry only runs up, past
/// it). The n digits, shifted up to the word's top (leading zeros below), are summed in three
/// multiplications (simdjson's eight-digit conversion).
#[inline(always)]
fn eight_digits(word: &[u8]) -> (usize, u64) {
    let mut bytes = [0u8; 8];
    bytes.copy_from_slice(&word[..8]);
    let x = u64::from_le_bytes(bytes) ^ 0x3030_3030_3030_3030;
    let flags = (x.wrapping_add(0x7676_7676_7676_7676) | x) & 0x8080_8080_8080_8080;
    let count = (flags.trailing_zeros() / 8) as usize;
    if count == 0 {
        return (0, 0);
    }
    let x = x << (8 * (8 - count));
    let x = x.wrapping_mul(10).wrapping_add(x >> 8);
    let x = ((x & 0x0000_00FF_0000_00FF).wrapping_mul(100 + (1_000_000 << 32))
        + ((x >> 16) & 0x0000_00FF_0000_00FF).wrapping_mul(1 + (10_000 << 32)))
        >> 32;
    (count, x)
}

/// The white space `str::trim` and `split_whitespace` remove, among ASCII bytes.
fn space(b: u8) -> bool {
    matches!(b, b' ' | b'\t' | b'\n' | b'\x0B' | b'\x0C' | b'\r')
}

/// A plain decimal at the start of `text`: its value and length, or `None` for anything else
/// (left to `str::parse`).
#[inline(always)]
fn decimal(text: &[u8]) -> Option<(f64, usize)> {
    let n = text.len();
    let negative = n > 0 && text[0] == b'-';
    let mut at = usize::from(n > 0 && (text[0] == b'-' || text[0] == b'+'));
    // Digits from `at` on, into the mantissa; how many. Eight bytes at a time while eight
    // remain ([`eight_digits`]), then byte by byte.
    let digits = |at: &mut usize, mantissa: &mut u64| {
        let start = *at;
        while let Some(word) = text.get(*at..*at + 8) {
            let (count, value) = eight_digits(word);
            *mantissa = mantissa.wrapping_mul(POWERS_U64[count]).wrapping_add(value);
            *at += count;
            if count < 8 {
                return *at - start;
            }
        }
        while *at < n && text[*at].wrapping_sub(b'0') < 10 {
            *mantissa = mantissa
                .wrapping_mul(10)
                .wrapping_add(u64::from(text[*at] - b'0'));
            *at += 1;
        }
        *at - start
    };
    let mut mantissa = 0u64;
    let whole = digits(&mut at, &mut mantissa);
    let mut after = 0;
    if at < n && text[at] == b'.' {
        at += 1;
        after = digits(&mut at, &mut mantissa);
    }
    // At most 19 digits cannot wrap a u64; below 2⁵³ the mantissa is an exact double.
    if whole + after == 0 || whole + after > 19 || after >= POWERS.len() || mantissa >= 1 << 53 {
        return None;
    }
    let value = mantissa as f64 / POWERS[after];
    Some((if negative { -value } else { value }, at))
}

/// A row of exactly `width` plain cells (time first), separated by commas (cells trimmed) when
/// the line has one, else by white space: its time, with the values appended to `values`. A
/// plain row has no lost value. `None` leaves the row to the general reader (and `values` as it
/// was).
pub(crate) fn plain_row(line: &[u8], width: usize, values: &mut Vec<f64>) -> Option<f64> {
    let start = values.len();
    let row = plain_cells(line, values).filter(|_| values.len() - start + 1 == width);
    if row.is_none() {
        values.truncate(start);
    }
    row
}

/// The cells of a plain row appended to `values` (see [`plain_row`]); its time.
fn plain_cells(line: &[u8], values: &mut Vec<f64>) -> Option<f64> {
    let n = line.len();
    let skip = |mut at: usize| {
        while at < n && space(line[at]) {
            at += 1;
        }
        at
    };
    // The separator, once seen: a comma, or white space (then no comma may follow).
    let mut comma = None;
    let mut at = skip(0);
    let (t, len) = decimal(&line[at..])?;
    at += len;
    loop {
        let end = at;
        at = skip(at);
        if at == n {
            break;
        }
        if line[at] == b',' && comma != Some(false) {
            comma = Some(true);
            at = skip(at + 1);
        } else if at > end && comma != Some(true) {
            comma = Some(false);
        } else {
            return None;
        }
        let (v, len) = decimal(&line[at..])?;
        values.push(v);
        at += len;
    }
    Some(t)
}

/// Two rows of exactly `width` plain cells separated by single commas (no white space but a
/// line end), read side by side: their times, the first row's values then the second's
/// appended to `values`. Reading one cell waits on the one before it (where it starts); two
/// rows give the processor two such chains to run at once (7 % less wall time on the
/// 10⁶-frame bench; four rows at once, no better). The values are those [`plain_row`] gives.
/// `None` (and `values` as it was) for any other pair.
pub(crate) fn comma_rows(
    lines: [&[u8]; 2],
    width: usize,
    values: &mut Vec<f64>,
) -> Option<[f64; 2]> {
    let start = values.len();
    let cells = width.checked_sub(1)?;
    values.resize(start + 2 * cells, 0.0);
    let read = |values: &mut [f64]| -> Option<[f64; 2]> {
        let [a, b] = lines;
        let ((t, mut i), (u, mut j)) = (decimal(a)?, decimal(b)?);
        let (first, second) = values.split_at_mut(cells);
        for (x, y) in first.iter_mut().zip(second) {
            if a.get(i) != Some(&b',') || b.get(j) != Some(&b',') {
                return None;
            }
            let ((v, m), (w, n)) = (decimal(&a[i + 1..])?, decimal(&b[j + 1..])?);
            (*x, *y) = (v, w);
            (i, j) = (i + 1 + m, j + 1 + n);
        }
        let end = |rest: &[u8]| matches!(rest, b"" | b"\n" | b"\r\n");
        (end(&a[i..]) && end(&b[j..])).then_some([t, u])
    };
    let times = read(&mut values[start..]);
    if times.is_none() {
        values.truncate(start);
    }
    times
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every plain decimal read fast is the double `str::parse` gives.
    #[test]
    fn decimals_match_the_standard_parser() {
        let mut next = crate::recording::xorshift(0x9E37_79B9_7F4A_7C15u64);
        for _ in 0..200_000 {
            let digits = 1 + next() % 18;
            let text: String = (0..digits)
                .map(|_| char::from(b'0' + (next() % 10) as u8))
                .collect();
            let point = (next() % (digits + 1)) as usize;
            let sign = ["", "-", "+"][(next() % 3) as usize];
            let cell = format!("{sign}{}.{}", &text[..point], &text[point..]);
            let want: f64 = cell.parse().unwrap();
            if let Some((got, len)) = decimal(cell.as_bytes()) {
                assert_eq!((got.to_bits(), len), (want.to_bits(), cell.len()), "{cell}");
            }
            // Inside a row, where eight bytes are read at a time across the cell's end.
            let row = format!("{cell},0.25,17\n");
            if let Some((got, len)) = decimal(row.as_bytes()) {
                assert_eq!((got.to_bits(), len), (want.to_bits(), cell.len()), "{row}");
            }
        }
        for cell in [
            "-0",
            "0.",
            ".5",
            "-0.000",
            "123456789012345",
            "0.1",
            "9007199254740991",
            "-.0000000000000001",
        ] {
            let want: f64 = cell.parse().unwrap();
            let got = decimal(cell.as_bytes()).map(|(v, len)| (v.to_bits(), len));
            assert_eq!(got, Some((want.to_bits(), cell.len())), "{cell}");
        }
        for cell in [
            "",
            ".",
            "-",
            "nan",
            "inf",
            "--1",
            "9007199254740992",
            "0.00000000000000000001",
        ] {
            assert_eq!(decimal(cell.as_bytes()), None, "{cell}");
        }
        // A number followed by more is read up to it; the row reader refuses the rest.
        assert_eq!(decimal(b"1e3"), Some((1.0, 1)));
        assert_eq!(decimal(b"1.2.3"), Some((1.2, 3)));
    }

    /// Two rows read side by side are what each gives alone; any pair but plain comma rows is
    /// declined, leaving the values as they were.
    #[test]
    fn rows_in_pairs_are_rows_alone() {
        let mut next = crate::recording::xorshift(0x51_7CC1_B727_220Au64);
        let cell = |r: u64| {
            let v = (r % 2_000_000_000) as f64 / 1e6 - 1000.0;
            let digits = (r >> 40) as usize % 9;
            format!("{v:.digits$}")
        };
        let row = |cells: Vec<String>, end: &str| cells.join(",") + end;
        for _ in 0..20_000 {
            let width = 2 + (next() % 30) as usize;
            let ends = ["\n", "\r\n", ""];
            let a = row(
                (0..width).map(|_| cell(next())).collect(),
                ends[(next() % 3) as usize],
            );
            let b = row(
                (0..width).map(|_| cell(next())).collect(),
                ends[(next() % 3) as usize],
            );
            let (mut one, mut two, mut both) = (Vec::new(), Vec::new(), vec![9.0]);
            let t = plain_row(a.as_bytes(), width, &mut one).unwrap();
            let u = plain_row(b.as_bytes(), width, &mut two).unwrap();
            let times = comma_rows([a.as_bytes(), b.as_bytes()], width, &mut both);
            let alone: Vec<f64> = [vec![9.0], one, two].concat();
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(
                times.map(|[t, u]| [t.to_bits(), u.to_bits()]),
                Some([t.to_bits(), u.to_bits()])
            );
            assert_eq!(bits(&both), bits(&alone), "{a:?} {b:?}");
        }
        let plain = b"1,2,3\n".as_slice();
        for other in [
            b"1, 2,3\n".as_slice(),
            b"1,2,3 \n",
            b"1,2\n",
            b"1,2,3,4\n",
            b"1,2,3,\n",
            b"1,2,NaN\n",
            b"1,,3\n",
            b"1 2 3\n",
            b"# 1,2,3\n",
            b"\n",
            b"1,2e0,3\n",
        ] {
            for pair in [[plain, other], [other, plain]] {
                let mut v = vec![7.0];
                assert_eq!(comma_rows(pair, 3, &mut v), None, "{pair:?}");
                assert_eq!(v, [7.0]);
            }
        }
    }

    /// Rows the fast reader declines are exactly the ones it cannot read plainly.
    #[test]
    fn rows_declined() {
        let mut v = vec![7.0];
        assert_eq!(plain_row(b" 1, 2 ,3\r", 3, &mut v), Some(1.0));
        assert_eq!(v, [7.0, 2.0, 3.0]);
        // A row declined leaves what was there.
        assert_eq!(plain_row(b"1,2,3,4", 3, &mut v), None);
        assert_eq!(v, [7.0, 2.0, 3.0]);
        v.clear();
        assert_eq!(plain_row(b"1 \t2\x0B3", 3, &mut v), Some(1.0));
        assert_eq!(plain_row(b"1,2", 3, &mut v), None);
        assert_eq!(plain_row(b"1,,3", 3, &mut v), None);
        assert_eq!(plain_row(b"1,NaN,3", 3, &mut v), None);
        assert_eq!(plain_row("1,2,3\u{a0}".as_bytes(), 3, &mut v), None);
        assert_eq!(plain_row(b"# 1,2,3", 3, &mut v), None);
        assert_eq!(plain_row(b"", 3, &mut v), None);
        assert_eq!(plain_row(b"1 2,3", 3, &mut v), None);
        assert_eq!(plain_row(b"1,2 3", 3, &mut v), None);
        assert_eq!(plain_row(b"1,2,3,", 3, &mut v), None);
        assert_eq!(plain_row(b"1,2e0,3", 3, &mut v), None);
        assert_eq!(plain_row(b"1,2,3\n", 3, &mut v), Some(1.0));
    }
}
