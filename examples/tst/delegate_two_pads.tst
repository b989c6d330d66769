# A small delegation (section 10): two branches that each point the PTU ahead and climb over one
# of the start pads, at the same time. No node names its agent: `hdrc3 delegate` auctions each
# branch among the agents' gateways. Concurrent branches need two aircraft (an aircraft flies one
# thing at a time), and each branch is cheapest for the aircraft standing on its pad.
world revinge
agents uav0, uav1, uav2

point OverH1 = H1 at 12
point OverH2 = H2 at 12

m(P0, TS0, TE0) = with P1, TS1, TE1, P2, TS2, TE2 concurrent
  a(P1, TS1, TE1) = with TS3, TE3, TS4, TE4 sequence
    a1(TS3, TE3) = ptu-turn-to(TS3, TE3, 0, 30);
    a2(TS4, TE4) = fly-to(TS4, TE4, 3, OverH1)
  where TS1 <= TS3 and TS3 < TE3 and TE3 <= TS4 and TS4 < TE4 and TE4 <= TE1;
  b(P2, TS2, TE2) = with TS5, TE5, TS6, TE6 sequence
    b1(TS5, TE5) = ptu-turn-to(TS5, TE5, 0, 30);
    b2(TS6, TE6) = fly-to(TS6, TE6, 3, OverH2)
  where TS2 <= TS5 and TS5 < TE5 and TE5 <= TS6 and TS6 < TE6 and TE6 <= TE2
where TS0 <= TS1 and TS1 < TE1 and TE1 <= TE0 and TS0 <= TS2 and TS2 < TE2 and TE2 <= TE0
  and TE0 <= 400
