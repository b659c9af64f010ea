"use strict";
// The page of several agents: one panel per agent (the one-agent page, served by the hub at
// agents/N/), added as agents join.
(function () {
  const token = new URLSearchParams(location.search).get("token");
  const query = token ? "?token=" + encodeURIComponent(token) : "";
  const agents = document.getElementById("agents");
  const roster = new EventSource("agents" + query);
  roster.onmessage = (e) => {
    const names = JSON.parse(e.data);
    if (!Array.isArray(names)) return;
    document.getElementById("count").textContent = names.length === 1 ? "1 agent" : `${names.length} agents`;
    for (let n = agents.children.length; n < names.length; n++) {
      const frame = document.createElement("iframe");
      frame.src = `agents/${n}/${query}`;
      frame.title = names[n];
      frame.dataset.agent = String(n);
      agents.append(frame);
    }
  };
})();
