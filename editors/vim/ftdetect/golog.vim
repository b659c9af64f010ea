" golog++ programs: the filetype golog (the language server's languageId too).
autocmd BufRead,BufNewFile *.gpp setfiletype golog
