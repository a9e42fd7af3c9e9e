# Contacts between LAMMPS rounded polygons, from a `dump local` of
# `compute body/local id 1 2` (one line per vertex: index, body id, x, y),
# as written by in.polygons. Two bodies touch when their vertex polygons
# come closer than the sum of the rounding radii (2 r), the test of
# pair_style body/rounded/polygon (vertex against edge, both ways).
# Periodic along x over the dump's box; prints the number of touching
# pairs and of bodies.
#
#   awk -v r=0.05 -f count_contacts.awk vertices.txt

function seg_dist2(px, py, ax, ay, bx, by,    ex, ey, t, l2, dx, dy) {
    ex = bx - ax; ey = by - ay
    l2 = ex * ex + ey * ey
    t = l2 > 0 ? ((px - ax) * ex + (py - ay) * ey) / l2 : 0
    if (t < 0) t = 0
    if (t > 1) t = 1
    dx = px - ax - t * ex; dy = py - ay - t * ey
    return dx * dx + dy * dy
}

# Squared distance between the vertex polygons of bodies i and j, j
# shifted by sx along x (its periodic image nearest to i).
function poly_dist2(i, j, sx,    a, b, a2, b2, d, best) {
    best = -1
    for (a = 1; a <= nv[i]; a++) {
        a2 = a % nv[i] + 1
        for (b = 1; b <= nv[j]; b++) {
            d = seg_dist2(vx[j, b] + sx, vy[j, b], vx[i, a], vy[i, a], vx[i, a2], vy[i, a2])
            if (best < 0 || d < best) best = d
        }
    }
    for (b = 1; b <= nv[j]; b++) {
        b2 = b % nv[j] + 1
        for (a = 1; a <= nv[i]; a++) {
            d = seg_dist2(vx[i, a], vy[i, a], vx[j, b] + sx, vy[j, b], vx[j, b2] + sx, vy[j, b2])
            if (d < best) best = d
        }
    }
    return best
}

/^ITEM: BOX BOUNDS/ { getline; xlo = $1; xhi = $2; next }
/^ITEM: ENTRIES/ { entries = 1; next }
/^ITEM:/ { entries = 0; next }
entries && NF >= 4 {
    id = $2
    if (!(id in nv)) { nv[id] = 0; ids[++n] = id }
    k = ++nv[id]
    vx[id, k] = $3; vy[id, k] = $4
}

END {
    if (n == 0) { print "count_contacts.awk: no vertices read" > "/dev/stderr"; exit 1 }
    if (r == "") { print "count_contacts.awk: set the rounding radius with -v r=..." > "/dev/stderr"; exit 1 }
    len = xhi - xlo
    # Centroid (vertex mean) and enclosing radius of each body.
    reach = 0
    for (m = 1; m <= n; m++) {
        id = ids[m]; sx = 0; sy = 0
        for (k = 1; k <= nv[id]; k++) { sx += vx[id, k]; sy += vy[id, k] }
        cx[id] = sx / nv[id]; cy[id] = sy / nv[id]
        rad = 0
        for (k = 1; k <= nv[id]; k++) {
            d = (vx[id, k] - cx[id]) ^ 2 + (vy[id, k] - cy[id]) ^ 2
            if (d > rad) rad = d
        }
        rad = sqrt(rad) + r
        if (rad > reach) reach = rad
    }
    # Cells of at least twice the largest enclosing radius, periodic in x.
    cell = 2 * reach
    ncx = int(len / cell); if (ncx < 1) ncx = 1
    wcx = len / ncx
    for (m = 1; m <= n; m++) {
        id = ids[m]
        x = cx[id] - xlo; x -= len * int(x / len); if (x < 0) x += len
        ix = int(x / wcx); if (ix >= ncx) ix = ncx - 1
        iy = int((cy[id] + 1e6 * cell) / cell)
        key = ix SUBSEP iy
        members[key] = members[key] " " id
        cellx[id] = ix; celly[id] = iy
    }
    touch2 = (2 * r) ^ 2
    pairs = 0
    for (m = 1; m <= n; m++) {
        i = ids[m]
        for (ox = -1; ox <= 1; ox++) {
            jx = (cellx[i] + ox + ncx) % ncx
            # With fewer than three cells along x, visit each cell once.
            if (ncx < 3 && ox != 0 && (ncx == 1 || ox == 1)) continue
            for (oy = -1; oy <= 1; oy++) {
                key = jx SUBSEP (celly[i] + oy)
                if (!(key in members)) continue
                c = split(members[key], list, " ")
                for (q = 1; q <= c; q++) {
                    j = list[q]
                    if (j + 0 <= i + 0) continue
                    dx = cx[j] - cx[i]
                    sx = -len * int(dx / len + (dx >= 0 ? 0.5 : -0.5))
                    dx += sx; dy = cy[j] - cy[i]
                    if (dx * dx + dy * dy > cell * cell) continue
                    if (poly_dist2(i, j, sx) < touch2) pairs++
                }
            }
        }
    }
    printf "%d %d\n", pairs, n
}
