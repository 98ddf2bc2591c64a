//! stride-muscle: Muscle models for stride: De Groote 2016 Hill model, activation dynamics, passive joint torques, metabolic energy models, polynomial muscle-tendon geometry.
