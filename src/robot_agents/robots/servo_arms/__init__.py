"""Low-cost servo arms: Koch v1.1 (:mod:`.koch`) and SO-100 (:mod:`.so100`), with their
servos and the derivation of their gains (:mod:`.servos`)."""
