"""The Python peer of `theory-search --basis monomials --order N --density both` (issue 16).

A straightforward Python loop: enumerate every product of derivative factors of one field
within the larva's bounds, decide the larva's rules as closed-form predicates on the factor
kinds, keep each field's lowest-order admitted terms, and print one line per candidate (term,
orders, marks), as the tool does. It reads nothing from the tool; the rules are written out here
by hand, which is exactly what the tool refuses to do (it derives them by applying each map).

Usage: python3 benches/peer_monomials.py [ORDER] [--quiet] > /dev/null
(--quiet decides and reduces without printing the table: the loop of the issue's figure.)
Compare: /usr/bin/time -f '%e s %M KB' python3 benches/peer_monomials.py 8 > /dev/null
         /usr/bin/time -f '%e s %M KB' theory-search --basis monomials --order 8 --density both > /dev/null
"""
import sys

SUP = str.maketrans("0123456789", "⁰¹²³⁴⁵⁶⁷⁸⁹")

# Factor kinds a rule shifts (φ → φ + p·sᵐtⁿ shifts ∂tᵃ∂sᵇφ when a ≤ n and b ≤ m).
SHIFTS = {"TRAN": (0, 0), "ROT": (1, 0), "GAL": (0, 1), "SPIN": (1, 1)}

LAGRANGIAN = {
    "columns": ["OST", "TRAN", "REF", "KIN", "ROT"],
    "fields": [("x", "OST TRAN REF KIN"), ("θ", "OST TRAN REF KIN"),
               ("y", "OST TRAN REF KIN ROT"), ("z", "OST TRAN REF KIN ROT")],
}
RAYLEIGH = {
    "columns": ["DIS", "TRAN", "GAL", "REF", "SPIN"],
    "fields": [("x", "DIS TRAN GAL REF"), ("θ", "DIS TRAN GAL REF"),
               ("y", "DIS TRAN GAL REF SPIN"), ("z", "DIS TRAN GAL REF SPIN")],
}


def kind_mask(a, b):
    """The shift rules that move the factor ∂tᵃ∂sᵇφ, as a bit set over SHIFTS."""
    return sum(1 << i for i, (m, n) in enumerate(SHIFTS.values()) if a <= n and b <= m)


SHIFT_BIT = {code: 1 << i for i, code in enumerate(SHIFTS)}


def verdicts(columns, factors, masks):
    moved = 0
    top = 0
    eps = 0
    all_one = True
    for (a, b), p in factors:
        moved |= masks[a][b]
        top = max(top, a)
        eps += p
        all_one = all_one and a == 1
    out = []
    for code in columns:
        if code in SHIFT_BIT:
            out.append(not moved & SHIFT_BIT[code])
        elif code == "REF":
            out.append(eps % 2 == 0)
        elif code == "OST":
            out.append(top <= 1)
        elif code == "KIN":
            out.append(top == 0 or factors == [((1, 0), 2)])
        elif code == "DIS":
            out.append(all_one)
        else:
            raise ValueError(code)
    return out


def monomials(order, tau_plus_sigma):
    kinds = [(a, b) for a in range(order + 1) for b in range(order + 1 - a)]
    out = []

    def fits(e, t, s):
        return e <= order and (t + s <= order if tau_plus_sigma else (t <= order and s <= order))

    def walk(start, chosen, eps, tau, sig):
        # One call per product: extend the prefix by each later kind, each power.
        if chosen:
            out.append(list(chosen))
        for j in range(start, len(kinds)):
            a, b = kinds[j]
            n = 1
            while fits(eps + n, tau + n * a, sig + n * b):
                chosen.append(((a, b), n))
                walk(j + 1, chosen, eps + n, tau + n * a, sig + n * b)
                chosen.pop()
                n += 1

    walk(0, [], 0, 0, 0)
    return out


def orders(factors):
    return (max(a + b for (a, b), _ in factors), sum(p for _, p in factors),
            sum(a * p for (a, _), p in factors), sum(b * p for (_, b), p in factors))


def letters(c, k):
    return c * k if k <= 4 else c + str(k).translate(SUP)


def render(factors):
    parts = []
    for (a, b), p in factors:
        d = ("∂" + letters("t", a) + letters("s", b) + " " if a + b else "") + "φ"
        if p > 1:
            d = (f"({d})" if a + b else d) + str(p).translate(SUP)
        parts.append(d)
    return "·".join(parts)


def density(name, spec, order, tau_plus_sigma, write):
    terms = [(orders(f), f) for f in monomials(order, tau_plus_sigma)]
    terms.sort(key=lambda t: (t[0][0], t[0][1]))
    cols = spec["columns"]
    masks = [[kind_mask(a, b) for b in range(order + 1)] for a in range(order + 1)]
    verdict = [verdicts(cols, f, masks) for _, f in terms]
    admitted = []
    for _, req in spec["fields"]:
        need = [cols.index(c) for c in req.split()]
        admitted.append([i for i, v in enumerate(verdict) if all(v[k] for k in need)])
    survivors = []
    for adm in admitted:
        orders_of = {(terms[i][0][2], terms[i][0][3]) for i in adm}
        front = {(t, s) for t, s in orders_of
                 if not any(u <= t and v <= s and (u, v) != (t, s) for u, v in orders_of)}
        survivors.append({i for i in adm if (terms[i][0][2], terms[i][0][3]) in front})
    if write is None:
        return
    write(f"{name} density: {len(terms)} candidate monomials\n")
    for i, (o, f) in enumerate(terms):
        marks = ["x" if v else "" for v in verdict[i]]
        marks += ["x" if i in s else "" for s in survivors]
        write(f"  {render(f)}  {o[0]}  {o[1]}  {o[2]}  {o[3]}  " + "  ".join(marks) + "\n")


def main():
    args = [a for a in sys.argv[1:] if a != "--quiet"]
    order = int(args[0]) if args else 8
    write = None if "--quiet" in sys.argv else sys.stdout.write
    density("Lagrangian", LAGRANGIAN, order, True, write)
    density("Rayleigh", RAYLEIGH, order, False, write)


if __name__ == "__main__":
    main()
