"""Running golog++ programs: values, state, the transition semantics and the online executor."""
