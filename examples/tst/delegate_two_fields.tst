# A short delegation (section 10): two small fields west of the pads, scanned at the same time.
# No node names its agent: `hdrc3 delegate` auctions each scan among the agents' gateways, and
# concurrent scans go to two aircraft because each one's constraint server schedules its own
# nodes one after the other (so a second scan on the same aircraft ends later).
world revinge
agents uav0, uav1, uav2

area North = polygon((-250, 0), (-210, 0), (-210, 30), (-250, 30))
area South = polygon((-250, -100), (-210, -100), (-210, -70), (-250, -70))

m(P0, TS0, TE0) = with P1, TS1, TE1, P2, TS2, TE2 concurrent
  n(P1, TS1, TE1) = scan-area(TS1, TE1, 6, North, 20);
  s(P2, TS2, TE2) = scan-area(TS2, TE2, 6, South, 20)
where TS0 <= TS1 and TS1 < TE1 and TE1 <= TE0 and TS0 <= TS2 and TS2 < TE2 and TE2 <= TE0
  and TE0 <= 600
