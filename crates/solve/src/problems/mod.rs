//! Test problems with known solutions (classic NLPs and a scalable collocation problem).
