"""The operator console (`gpp run --console`): a page that shows a run live and steers it
(docs/console.md). `state` folds the run's records into what the page shows, `control` is the
run control that holds, starts and stops the run, `access` decides who may, and `server` (the
only module that imports the web libraries) serves the page `page.*`."""
