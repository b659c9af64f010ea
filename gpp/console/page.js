"use strict";
// The console's page: one live stream of the run's view (server-sent events), one POST per
// operator request with the token in a header (never a cookie).
(function () {
  const token = new URLSearchParams(location.search).get("token");
  const $ = (id) => document.getElementById(id);
  const values = new Map();   // fluent -> value shown
  let formsKey = "";
  let view = null;

  function el(tag, attrs, ...children) {
    const node = document.createElement(tag);
    for (const [k, v] of Object.entries(attrs || {})) {
      if (k === "class") node.className = v; else if (k.startsWith("data-")) node.setAttribute(k, v); else node[k] = v;
    }
    for (const c of children) node.append(c instanceof Node ? c : String(c));
    return node;
  }

  function fixed(x) { return typeof x === "number" ? x.toFixed(3) : "–"; }

  function send(command, action, args) {
    const headers = { "Content-Type": "application/json" };
    if (token) headers["X-Gpp-Token"] = token;
    $("message").textContent = "";
    return fetch("control", { method: "POST", headers, body: JSON.stringify({ command, action, args }) })
      .then((r) => r.json().then((body) => { if (!r.ok) $("message").textContent = body.error || r.statusText; }))
      .catch((e) => { $("message").textContent = String(e); });
  }

  for (const button of document.querySelectorAll("nav button")) {
    button.addEventListener("click", () => send(button.dataset.command));
  }

  function renderFluents(fluents) {
    const body = $("fluents").tBodies[0];
    const filter = $("filter").value.trim().toLowerCase();
    body.replaceChildren();
    for (const f of fluents) {
      if (filter && !f.name.toLowerCase().includes(filter)) continue;
      const before = values.get(f.name);
      const row = el("tr", { "data-fluent": f.name }, el("td", {}, f.name), el("td", { class: "value" }, f.value));
      if (before !== undefined && before !== f.value) row.classList.add("changed");
      body.append(row);
    }
    for (const f of fluents) values.set(f.name, f.value);
    $("fluents-note").textContent = view.fluents_left_out ? `${view.fluents_left_out} more instances are not shown until set` : "";
  }

  function form(kind, spec) {
    const inputs = spec.parameters.map((p) => {
      let input;
      if (p.kind === "choice") {
        input = el("select", { name: p.name }, ...p.choices.map((c) => el("option", { value: c }, c)));
      } else {
        input = el("input", { name: p.name, type: p.kind === "number" ? "number" : "text", step: "any",
          placeholder: p.kind === "json" ? "JSON" : p.kind });
      }
      return el("label", {}, p.name, input);
    });
    const button = el("button", { type: "submit", class: "small" }, kind === "exog" ? "Send" : "Run");
    const f = el("form", { "data-action": spec.name }, el("span", { class: "name" }, spec.name), ...inputs, button);
    f.addEventListener("submit", (e) => {
      e.preventDefault();
      const args = {};
      for (const p of spec.parameters) args[p.name] = f.elements[p.name].value;
      send(kind, spec.name, args);
    });
    return f;
  }

  function renderForms() {
    const key = JSON.stringify([view.exogenous, view.actions]);
    if (key !== formsKey) {
      formsKey = key;
      $("exog-forms").replaceChildren(...view.exogenous.map((s) => form("exog", s)));
      $("act-forms").replaceChildren(...view.actions.map((s) => form("act", s)));
    }
    $("exog-box").hidden = view.exogenous.length === 0;
    $("act-box").hidden = !view.can.act || view.actions.length === 0;
    for (const b of document.querySelectorAll("#exog-forms button")) b.disabled = !view.can.exog;
    for (const b of document.querySelectorAll("#act-forms button")) b.disabled = !view.can.act;
  }

  function render(data) {
    view = data;
    const status = data.closed && ["running", "paused", "waiting for Start", "starting"].includes(data.status)
      ? "disconnected" : data.status;
    $("status").textContent = status;
    $("status").dataset.status = status;
    document.body.dataset.status = status;
    document.body.dataset.records = data.records;
    $("clock").textContent = fixed(data.clock);
    if (data.agent.program) {
      $("program").textContent = data.agent.program;
      $("platform").textContent = "on " + data.agent.platform + (data.agent.node ? " " + data.agent.node : "");
      document.title = data.agent.program + " – gpp console";
    }
    for (const button of document.querySelectorAll("nav button")) button.disabled = !data.can[button.dataset.command];
    const w = data.waiting;
    $("waiting").textContent = w ? `${w.condition}: ${w.statement}${w.at ? " at " + w.at : ""}` : "nothing";
    $("problem").textContent = data.problem || "";
    $("activities").tBodies[0].replaceChildren(...data.activities.map((a) => el("tr", { "data-activity": a.action },
      el("td", {}, a.action), el("td", {}, a.status + (a.cancelling ? " (cancelling)" : "")),
      el("td", { class: "value" }, fixed(a.elapsed) + " s"),
      el("td", { class: "value" }, Object.entries(a.args).map(([k, v]) => `${k}=${v}`).join(" ")))));
    const plan = data.plan;
    $("plan-none").hidden = !!(plan && plan.policy.length);
    $("plan").replaceChildren(...(plan ? plan.policy.map((step, i) => el("li", {
      class: i < plan.step - 1 ? "done" : i === plan.step - 1 ? "current" : "" }, step)) : []));
    if (plan && !plan.feasible) $("plan-none").textContent = `${plan.kind} found no feasible plan`;
    renderFluents(data.fluents);
    renderForms();
    $("failures").replaceChildren(...data.failures.map((f) => el("li", {}, `${fixed(f.t)} ${f.action}${f.reason ? ": " + f.reason : ""}`)));
    const events = $("events");
    events.replaceChildren(...data.events.map((e) => el("li", { class: e.kind }, `${fixed(e.t)}  ${e.text}`)));
    events.scrollTop = events.scrollHeight;
  }

  $("filter").addEventListener("input", () => view && renderFluents(view.fluents));

  const stream = new EventSource("events" + (token ? "?token=" + encodeURIComponent(token) : ""));
  stream.onmessage = (e) => {
    const data = JSON.parse(e.data);
    render(data);
    if (data.closed) stream.close();
  };
  stream.onerror = () => {
    if (stream.readyState === EventSource.CLOSED || (view && view.closed)) {
      stream.close();
      if (view && !view.closed) { $("status").textContent = "disconnected"; $("status").dataset.status = "disconnected"; }
    }
  };
})();
